# Every dependency comes from a Debian 12 package; scripts/install-deps.sh installs them all.
find_package(PkgConfig REQUIRED)
find_package(PNG REQUIRED)                      # libpng-dev
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)   # libstb-dev: JPEG/TGA/BMP decoding
find_package(tinyexr REQUIRED)                  # libtinyexr-dev
find_package(glm REQUIRED)                      # libglm-dev
find_package(Eigen3 REQUIRED NO_MODULE)         # libeigen3-dev
find_package(CLI11 REQUIRED)                    # libcli11-dev
find_package(nlohmann_json REQUIRED)            # nlohmann-json3-dev
find_package(TBB REQUIRED)                      # libtbb-dev
find_package(Threads REQUIRED)
find_package(tinyobjloader REQUIRED)           # libtinyobjloader-dev: OBJ meshes
find_package(TinyGLTF REQUIRED)                 # libtinygltf-dev: glTF 2.0 meshes (a shared library on Debian)
# The gl layer: OpenGL 4.5 core through libepoxy (libepoxy-dev), headless through EGL (libegl-dev,
# libegl-mesa0, libgl1-mesa-dri: Mesa, llvmpipe without a GPU). libepoxy resolves both GL and EGL.
pkg_check_modules(EPOXY REQUIRED IMPORTED_TARGET epoxy)
if(STRATA_BUILD_TESTS)
  find_package(GTest REQUIRED)                  # libgtest-dev
endif()
if(STRATA_BUILD_BENCH)
  find_package(benchmark REQUIRED)              # libbenchmark-dev
endif()
