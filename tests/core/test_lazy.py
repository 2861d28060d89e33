"""Tests for mtcal.core.lazy: the layers' lazy ``__getattr__`` / ``__dir__``."""

import sys

import pytest

from mtcal.core.lazy import lazy_attributes


def test_submodule_and_export_load_on_access_and_are_cached():
    namespace = {"__name__": "json", "__all__": ["decoder", "JSONDecoder"]}
    getattr_, dir_ = lazy_attributes(namespace, ("decoder",), {"JSONDecoder": "decoder"})
    assert getattr_("decoder") is sys.modules["json.decoder"]
    assert "decoder" not in namespace                      # a submodule is an attribute of its package
    cls = getattr_("JSONDecoder")
    assert cls is sys.modules["json.decoder"].JSONDecoder and namespace["JSONDecoder"] is cls
    assert dir_() == ["JSONDecoder", "__all__", "__name__", "decoder"]


def test_unknown_name_is_an_attribute_error():
    getattr_, _ = lazy_attributes({"__name__": "json", "__all__": []}, ("decoder",), {})
    with pytest.raises(AttributeError, match="module 'json' has no attribute 'JSONDecoder'"):
        getattr_("JSONDecoder")


@pytest.mark.parametrize("package", ["mtcal.core", "mtcal.methods", "mtcal.filters", "mtcal.reporting",
                                     "mtcal.systems"])
def test_every_layer_resolves_its_all(package):
    import importlib

    mod = importlib.import_module(package)
    for name in mod.__all__:
        assert getattr(mod, name) is not None, name
    assert set(mod.__all__) <= set(dir(mod))
    with pytest.raises(AttributeError, match=f"module '{package}' has no attribute 'no_such_name'"):
        getattr(mod, "no_such_name")
