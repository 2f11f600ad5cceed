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
if(SDFBRICK_BUILD_TESTS)
    find_package(GTest REQUIRED)                    # libgtest-dev
endif()
if(SDFBRICK_BUILD_BENCH)
    find_package(benchmark REQUIRED)                # libbenchmark-dev
endif()
# The kernels are OpenCL C 1.2; the host asks for 1.2 entry points only.
set(SDFBRICK_CL_DEFINES CL_TARGET_OPENCL_VERSION=120 CL_USE_DEPRECATED_OPENCL_1_2_APIS)
