# Every dependency is a Debian package; a missing one fails with the package name to install
# (scripts/install-deps.sh installs them all).
include(FindPkgConfig)

function(parallax_require_package found_var debian_package what)
  if(NOT ${found_var})
    message(FATAL_ERROR "${what} not found: install the Debian package '${debian_package}' "
                        "(or run scripts/install-deps.sh)")
  endif()
endfunction()

find_package(Threads REQUIRED)

find_package(TBB CONFIG QUIET)
parallax_require_package(TBB_FOUND libtbb-dev "oneTBB")

find_package(CLI11 CONFIG QUIET)
parallax_require_package(CLI11_FOUND libcli11-dev "CLI11")

# E57's XML section (io/e57/e57_document.cpp).
find_package(LibXml2 QUIET)
parallax_require_package(LibXml2_FOUND libxml2-dev "libxml2")

find_package(nlohmann_json CONFIG QUIET)
parallax_require_package(nlohmann_json_FOUND nlohmann-json3-dev "nlohmann JSON")

# The ground's triangulation of src/terrain (--height-above-ground): CGAL's 2D Delaunay
# triangulation, header only.
find_package(CGAL CONFIG QUIET)
parallax_require_package(CGAL_FOUND libcgal-dev "CGAL")
# Rasters of src/raster (GeoTIFF and PNG writing, reading rasters back): GDAL 3.6.
find_package(GDAL CONFIG QUIET)
parallax_require_package(GDAL_FOUND libgdal-dev "GDAL")

# HTTP(S) byte ranges (src/net): libcurl, OpenSSL flavour (HTTP/2 through nghttp2).
pkg_check_modules(libcurl QUIET IMPORTED_TARGET libcurl)
parallax_require_package(libcurl_FOUND libcurl4-openssl-dev "libcurl")

find_path(PARALLAX_FAST_FLOAT_INCLUDE fast_float/fast_float.h)
parallax_require_package(PARALLAX_FAST_FLOAT_INCLUDE libfast-float-dev "fast_float")
add_library(parallax_fast_float INTERFACE)
target_include_directories(parallax_fast_float SYSTEM INTERFACE ${PARALLAX_FAST_FLOAT_INCLUDE})
add_library(parallax::fast_float ALIAS parallax_fast_float)

# LZF, the compression of PCD's binary_compressed data (PCL's own copy is liblzf's format).
find_path(PARALLAX_LZF_INCLUDE liblzf/lzf.h)
find_library(PARALLAX_LZF_LIBRARY lzf)
parallax_require_package(PARALLAX_LZF_INCLUDE liblzf-dev "liblzf")
parallax_require_package(PARALLAX_LZF_LIBRARY liblzf-dev "liblzf")
add_library(parallax_lzf INTERFACE)
target_include_directories(parallax_lzf SYSTEM INTERFACE ${PARALLAX_LZF_INCLUDE})
target_link_libraries(parallax_lzf INTERFACE ${PARALLAX_LZF_LIBRARY})
add_library(parallax::lzf ALIAS parallax_lzf)

if(PARALLAX_BUILD_TESTS)
  find_package(GTest CONFIG QUIET)
  parallax_require_package(GTest_FOUND libgtest-dev "GoogleTest")
endif()
if(PARALLAX_BUILD_BENCH)
  find_package(benchmark CONFIG QUIET)
  parallax_require_package(benchmark_FOUND libbenchmark-dev "Google Benchmark")
endif()

# Rendering (src/render, src/viewer). GL functions come from libepoxy, which loads them through
# EGL or GLX alike; the headless context is EGL's.
pkg_check_modules(epoxy QUIET IMPORTED_TARGET epoxy)
parallax_require_package(epoxy_FOUND libepoxy-dev "libepoxy")
pkg_check_modules(egl QUIET IMPORTED_TARGET egl)
parallax_require_package(egl_FOUND libegl-dev "EGL")
find_package(glm CONFIG QUIET)
parallax_require_package(glm_FOUND libglm-dev "GLM")
# Debian's libstb is a compiled library (stb_image, stb_image_write, ...).
pkg_check_modules(stb QUIET IMPORTED_TARGET stb)
parallax_require_package(stb_FOUND libstb-dev "stb")
pkg_check_modules(glfw3 QUIET IMPORTED_TARGET glfw3)
parallax_require_package(glfw3_FOUND libglfw3-dev "GLFW 3")
pkg_check_modules(imgui QUIET IMPORTED_TARGET imgui)
parallax_require_package(imgui_FOUND libimgui-dev "Dear ImGui")
# VR (src/xr, `view --xr`): the Khronos OpenXR loader. On by default where it is found.
find_package(OpenXR CONFIG QUIET)
option(PARALLAX_XR "Build VR through OpenXR (parallax view --xr)" ${OpenXR_FOUND})
if(PARALLAX_XR)
  parallax_require_package(OpenXR_FOUND "libopenxr-dev libopenxr-loader1" "OpenXR loader")
  # The Xlib/GLX binding of XR_KHR_opengl_enable (a window's context) hands the runtime X11
  # objects; libX11 frees what GLX returns.
  find_package(X11 QUIET)
  parallax_require_package(X11_FOUND libx11-dev "Xlib")
endif()
