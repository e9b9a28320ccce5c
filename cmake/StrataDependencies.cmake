# Every dependency comes from a Debian 12 package; scripts/install-deps.sh installs them all.
find_package(PkgConfig REQUIRED)
find_package(PNG REQUIRED)                      # libpng-dev
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)   # libstb-dev: TGA/BMP decoding
find_package(JPEG REQUIRED)                     # libjpeg62-turbo-dev: JPEG decoding that reports corrupt data
find_package(tinyexr REQUIRED)                  # libtinyexr-dev
find_package(glm REQUIRED)                      # libglm-dev
find_package(Eigen3 REQUIRED NO_MODULE)         # libeigen3-dev
find_package(CLI11 REQUIRED)                    # libcli11-dev
find_package(nlohmann_json REQUIRED)            # nlohmann-json3-dev
find_package(TBB REQUIRED)                      # libtbb-dev
find_package(Threads REQUIRED)
find_package(tinyobjloader REQUIRED)           # libtinyobjloader-dev: OBJ meshes
find_package(TinyGLTF REQUIRED)                 # libtinygltf-dev: glTF 2.0 meshes (a shared library on Debian)
find_package(Boost 1.74 REQUIRED)               # Boost's headers (libboost1.74-dev, which libboost-iostreams-dev brings): Boost.Math's Gauss-Legendre rules
# The gdm module (generalized displacement maps): Embree 3 (libembree-dev) casts the bake's and the exact
# reference's rays against triangle meshes; OpenVDB (libopenvdb-dev) reads level sets and meshes them. Its
# Find module ships with the package and needs Boost.Iostreams (libboost-iostreams-dev).
find_package(embree 3 REQUIRED)
list(APPEND CMAKE_MODULE_PATH /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB)
find_package(OpenVDB REQUIRED)
# Spectra (libspectra-dev, header-only, on Eigen): the k largest eigenpairs of the GDM SVD's Gram matrix
# where it is too large to diagonalise whole.
find_package(Spectra REQUIRED)
# The gl layer: OpenGL 4.5 core through libepoxy (libepoxy-dev), headless through EGL (libegl-dev,
# libegl-mesa0, libgl1-mesa-dri: Mesa, llvmpipe without a GPU). libepoxy resolves both GL and EGL.
pkg_check_modules(EPOXY REQUIRED IMPORTED_TARGET epoxy)

# --- The viewer (apps/strata-view) -----------------------------------------------------------------------
# GLFW windows (libglfw3-dev) and Dear ImGui (libimgui-dev 1.86: a static libimgui.a with the GLFW and
# OpenGL 3 backends compiled in, headers under /usr/include/imgui, and imgui.pc). ImGui's OpenGL 3 backend
# loads GL through its own bundled gl3w (libGL.so.1 + glXGetProcAddress), Strata's code through libepoxy;
# both serve the GLFW window's 4.5 core context. Tests run the viewer under xvfb-run (xvfb, xauth).
# OFF builds everything else; the viewer's end-to-end tests then skip.
option(STRATA_BUILD_VIEWER "Build the interactive viewer strata-view (GLFW + Dear ImGui)" ON)
if(STRATA_BUILD_VIEWER)
  find_package(glfw3 3.3 REQUIRED)              # libglfw3-dev
  pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)   # libimgui-dev
endif()
# ----------------------------------------------------------------------------------------------------------

if(STRATA_BUILD_TESTS)
  find_package(GTest REQUIRED)                  # libgtest-dev
endif()
if(STRATA_BUILD_BENCH)
  find_package(benchmark REQUIRED)              # libbenchmark-dev
endif()
