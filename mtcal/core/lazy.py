"""Lazy package attributes (PEP 562): submodules and re-exported names load on first access.

Every layer's ``__init__`` lists its submodules and re-exported names and gets its module
``__getattr__`` / ``__dir__`` from :func:`lazy_attributes`, so ``import mtcal`` (and a CLI
call) loads neither numba, scipy nor pandas until a name needs them.

Examples
--------
>>> namespace = {"__name__": "json", "__all__": ["decoder", "JSONDecoder"]}
>>> getattr_, dir_ = lazy_attributes(namespace, ("decoder",), {"JSONDecoder": "decoder"})
>>> getattr_("decoder").__name__, getattr_("JSONDecoder").__name__, "JSONDecoder" in namespace
('json.decoder', 'JSONDecoder', True)
>>> dir_()
['JSONDecoder', '__all__', '__name__', 'decoder']
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Collection, Mapping

__all__ = ["lazy_attributes"]


def lazy_attributes(namespace: dict, submodules: Collection[str],
                    exports: Mapping[str, str]) -> tuple[Callable[[str], object], Callable[[], list]]:
    """Module ``__getattr__`` and ``__dir__`` for a package that loads its contents on first use.

    Parameters
    ----------
    namespace : dict
        The package's ``globals()`` (needs ``__name__`` and ``__all__``); a re-exported name is
        stored there on first access, so the next access is a plain lookup.
    submodules : collection of str
        Submodule names, imported on access (``package.submodule``).
    exports : mapping of str to str
        Re-exported name → submodule defining it.

    Returns
    -------
    (__getattr__, __dir__)
        ``__getattr__(name)`` raises ``AttributeError`` for any other name; ``__dir__()`` lists
        the namespace and ``__all__``, sorted.

    Examples
    --------
    >>> getattr_, _ = lazy_attributes({"__name__": "json", "__all__": []}, (), {})
    >>> getattr_("nope")
    Traceback (most recent call last):
    ...
    AttributeError: module 'json' has no attribute 'nope'
    """
    package = namespace["__name__"]

    def __getattr__(name: str):
        if name in submodules:
            return importlib.import_module(f"{package}.{name}")
        if name in exports:
            value = getattr(importlib.import_module(f"{package}.{exports[name]}"), name)
            namespace[name] = value
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__() -> list:
        return sorted(set(namespace) | set(namespace["__all__"]))

    return __getattr__, __dir__
