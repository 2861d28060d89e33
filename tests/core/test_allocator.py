import ctypes
import sys

from mtcal.core import allocator


class _FakeLibc:
    def __init__(self, calls):
        self.calls = calls

    def mallopt(self, param, value):
        self.calls.append((param, value))
        return 1


def test_keep_freed_memory_sets_the_thresholds_on_linux_only(monkeypatch):
    """glibc's mmap/trim thresholds and top pad (values only, never results); no libc or not Linux: no-op."""
    calls = []
    monkeypatch.setattr(sys, "platform", "linux")
    monkeypatch.setattr(ctypes, "CDLL", lambda name: _FakeLibc(calls))
    allocator.keep_freed_memory()
    assert calls == [(-3, 1 << 30), (-1, 1 << 30), (-2, 64 << 20)] == list(allocator.MALLOPT.items())

    def no_libc(name):
        raise OSError("no libc")

    monkeypatch.setattr(ctypes, "CDLL", no_libc)
    allocator.keep_freed_memory()                      # silently nothing
    monkeypatch.setattr(sys, "platform", "darwin")
    monkeypatch.setattr(ctypes, "CDLL", lambda name: _FakeLibc(calls))
    allocator.keep_freed_memory()
    assert len(calls) == 3


def test_the_real_allocator_accepts_the_settings():
    allocator.keep_freed_memory()                      # on this machine's libc: no error, idempotent
    allocator.keep_freed_memory()
