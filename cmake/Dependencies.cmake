# Dependency discovery. Everything comes from Debian packages (tools/install-deps.sh installs them).
find_package(OpenCL REQUIRED)                       # ocl-icd-opencl-dev + opencl-headers
find_package(nlohmann_json 3 REQUIRED)              # nlohmann-json3-dev
find_package(CLI11 REQUIRED)                        # libcli11-dev
find_package(glm REQUIRED)                          # libglm-dev
find_package(fmt REQUIRED)                          # libfmt-dev
find_package(Threads REQUIRED)
find_package(assimp REQUIRED)                       # libassimp-dev: mesh files (OBJ, PLY, ...)
find_package(PkgConfig REQUIRED)
pkg_check_modules(sodium REQUIRED IMPORTED_TARGET libsodium)  # libsodium-dev: the program cache's MAC
if(SDFBRICK_WITH_OIIO)
    # libopenimageio-dev. Through pkg-config: Debian 12's CMake config of OpenImageIO names
    # /usr/include/opencv4 as an include directory, which exists only with OpenCV's headers installed.
    pkg_check_modules(OpenImageIO REQUIRED IMPORTED_TARGET OpenImageIO)
endif()
if(SDFBRICK_WITH_OPENVDB)
    # libopenvdb-dev ships its find module (FindOpenVDB.cmake) rather than a config file.
    list(APPEND CMAKE_MODULE_PATH "/usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB")
    find_package(OpenVDB REQUIRED COMPONENTS openvdb)
endif()
if(SDFBRICK_WITH_NANOVDB)
    # libnanovdb-dev: headers only.
    find_path(NANOVDB_INCLUDE_DIR nanovdb/NanoVDB.h REQUIRED)
endif()
# The Python module (pybind11-dev, python3-dev): on by default where pybind11 is found, except in
# sanitizer builds (the debug preset), whose module an uninstrumented interpreter cannot load. It is
# built for the system interpreter /usr/bin/python3 unless Python_EXECUTABLE names another.
if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Interpreter the Python module is built for")
endif()
if(NOT DEFINED PYTHON_EXECUTABLE)
    set(PYTHON_EXECUTABLE "${Python_EXECUTABLE}" CACHE FILEPATH "Interpreter the Python module is built for")
endif()
set(PYBIND11_FINDPYTHON ON)
find_package(pybind11 CONFIG QUIET)
set(python_default ${pybind11_FOUND})
if(CMAKE_CXX_FLAGS MATCHES "-fsanitize")
    set(python_default OFF)
endif()
option(SDFBRICK_WITH_PYTHON "Build the Python module sdfbrick (pybind11-dev)" ${python_default})
if(SDFBRICK_WITH_PYTHON AND NOT pybind11_FOUND)
    find_package(pybind11 CONFIG REQUIRED)
endif()
if(SDFBRICK_BUILD_TESTS)
    find_package(GTest REQUIRED)                    # libgtest-dev
endif()
if(SDFBRICK_BUILD_BENCH)
    find_package(benchmark REQUIRED)                # libbenchmark-dev
endif()
# The kernels are OpenCL C 1.2; the host asks for 1.2 entry points only.
set(SDFBRICK_CL_DEFINES CL_TARGET_OPENCL_VERSION=120 CL_USE_DEPRECATED_OPENCL_1_2_APIS)
