"""python/setup.py's choice of the CUDA backend, the same rule as CMake's
CURRAY_CUDA=AUTO: CUDA only with nvcc and an NVIDIA driver, unless
CURRAY_CUDA=1 (or CURRAY_GPU_LIB) asks for it or CURRAY_CUDA=0 refuses it.
setup.py is run with setuptools.setup replaced, so nothing is built."""
import os
import runpy

import pytest
import setuptools

SETUP = os.path.join(os.environ.get("CURRAY_SOURCE_DIR",
                                    os.path.join(os.path.dirname(__file__), "..", "..")),
                     "python", "setup.py")


@pytest.fixture
def setup_py(monkeypatch):
    monkeypatch.setattr(setuptools, "setup", lambda **kw: None)
    return runpy.run_path(SETUP)


@pytest.mark.parametrize("want, lib, nvcc, driver, use, why", [
    (None, None, "/cuda/bin/nvcc", "/proc/driver/nvidia/version", True,
     "CURRAY_CUDA unset: nvcc and an NVIDIA driver (/proc/driver/nvidia/version) found"),
    (None, None, "/cuda/bin/nvcc", None, False,
     "CURRAY_CUDA unset: nvcc found (/cuda/bin/nvcc) but no NVIDIA driver on this machine; "
     "CURRAY_CUDA=1 builds it anyway"),
    (None, None, None, "/proc/driver/nvidia/version", False, "nvcc not found"),
    (True, None, "/cuda/bin/nvcc", None, True, "CURRAY_CUDA=1"),
    (None, "/b/libcurray_gpu.a", "/cuda/bin/nvcc", None, True, "CURRAY_GPU_LIB=/b/libcurray_gpu.a"),
    (False, None, "/cuda/bin/nvcc", "/proc/driver/nvidia/version", False, "CURRAY_CUDA=0"),
    (False, "/b/libcurray_gpu.a", None, None, False, "CURRAY_CUDA=0"),
])
def test_cuda_choice(setup_py, want, lib, nvcc, driver, use, why):
    assert setup_py["cuda_choice"](want, lib, nvcc, driver) == (use, why)


@pytest.mark.parametrize("want, lib", [(True, None), (None, "/b/libcurray_gpu.a")])
def test_cuda_asked_without_nvcc_fails(setup_py, want, lib):
    with pytest.raises(SystemExit, match="nvcc .* was not found"):
        setup_py["cuda_choice"](want, lib, None, None)


def test_find_driver_file(setup_py, monkeypatch, tmp_path):
    f = tmp_path / "version"
    monkeypatch.setenv("CURRAY_NVIDIA_DRIVER_FILE", str(f))
    assert setup_py["find_driver"]() is None
    f.write_text("NVRM version: stand-in\n")
    assert setup_py["find_driver"]() == str(f)


@pytest.mark.parametrize("value, switch", [("", None), ("auto", None), ("1", True), ("ON", True),
                                           ("0", False), ("off", False)])
def test_env_switch(setup_py, monkeypatch, value, switch):
    monkeypatch.setenv("CURRAY_CUDA", value)
    assert setup_py["env_switch"]("CURRAY_CUDA") is switch
