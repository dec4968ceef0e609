# Whether to build the Python module (python/): PENUMBRA_PYTHON, on by default where
# pybind11 and Python's headers are found (tools/setup installs Debian's pybind11-dev and
# python3-dev; pip install . brings pybind11 from PyPI). Included before the layers: the
# module links them into a shared object, so penumbra_add_layer (cmake/Layers.cmake) and
# the embedded shaders compile position-independent code where it is on.
include_guard(GLOBAL)

find_package(Python 3.8 COMPONENTS Interpreter Development.Module)
if(Python_FOUND)
  find_package(pybind11 2.10 CONFIG QUIET)
endif()
set(PENUMBRA_PYTHON_DEFAULT OFF)
if(Python_FOUND AND pybind11_FOUND)
  set(PENUMBRA_PYTHON_DEFAULT ON)
endif()
option(PENUMBRA_PYTHON "build the Python module penumbra (needs pybind11 and Python's headers)"
       ${PENUMBRA_PYTHON_DEFAULT})
if(PENUMBRA_PYTHON)
  if(NOT pybind11_FOUND)
    message(FATAL_ERROR "PENUMBRA_PYTHON needs pybind11 (Debian: pybind11-dev python3-dev)")
  endif()
endif()
