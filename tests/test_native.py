"""sdn3d's C++ kernels (sdn3d.native): each one's failed build warns and leaves its PyTorch path, and each is built
once into the cache and reused."""

from __future__ import annotations

import warnings

import pytest
from helpers.native import needs_compiler

import sdn3d.editing.photo.nearest as nearest
import sdn3d.editing.photo.road as road
import sdn3d.render._native as soft_native

#: (the kernel's cached loader, its library's file stem, what its warning names)
KERNELS = {
    "soft silhouette": (soft_native.soft_kernel, "soft_kernel", "the soft silhouette uses its PyTorch path"),
    "nearest examples": (nearest.nearest_kernel, "nearest_kernel", "nearest examples uses its PyTorch path"),
    "photo rays": (road.ray_kernel, "ray_kernel", "the photo's ray fill uses its PyTorch path"),
}


@pytest.mark.parametrize("name", KERNELS)
def test_a_failed_build_warns_and_falls_back(monkeypatch, tmp_path, name) -> None:
    loader, _, message = KERNELS[name]
    monkeypatch.setenv("SDN3D_NATIVE_CACHE", str(tmp_path))
    monkeypatch.setenv("CXX", "false")  # a "compiler" that always fails
    loader.cache_clear()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            assert loader() is None
        assert any(message in str(w.message) for w in caught), [str(w.message) for w in caught]
        assert not list(tmp_path.glob("*.so"))
    finally:
        loader.cache_clear()


@needs_compiler
@pytest.mark.parametrize("name", KERNELS)
def test_the_kernel_is_built_once_into_the_cache(monkeypatch, tmp_path, name) -> None:
    loader, stem, _ = KERNELS[name]
    monkeypatch.setenv("SDN3D_NATIVE_CACHE", str(tmp_path))
    loader.cache_clear()
    try:
        assert loader() is not None
        built = list(tmp_path.glob(f"{stem}_*.so"))
        assert len(built) == 1
        stamp = built[0].stat().st_mtime_ns
        loader.cache_clear()
        assert loader() is not None and built[0].stat().st_mtime_ns == stamp  # reused, not rebuilt
    finally:
        loader.cache_clear()


def test_without_a_compiler_each_kernel_says_so(monkeypatch, tmp_path) -> None:
    monkeypatch.setenv("SDN3D_NATIVE_CACHE", str(tmp_path))
    monkeypatch.setattr("sdn3d.native.compiler", lambda: None)
    for loader, _, _ in KERNELS.values():
        loader.cache_clear()
    try:
        for name, (loader, _, _) in KERNELS.items():
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                assert loader() is None
            assert any("no C++ compiler" in str(w.message) for w in caught), name
    finally:
        for loader, _, _ in KERNELS.values():
            loader.cache_clear()
