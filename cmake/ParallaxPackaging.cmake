# Installation, the Debian package, and what `parallax --version` reports.
#
#   cmake --install build --prefix /opt/parallax     bin/parallax and its documents
#   cpack --config build/CPackConfig.cmake -G DEB    parallax_VERSION_ARCH.deb, its dependencies
#                                                    read off the binary by dpkg-shlibdeps
# Included at the end of the top CMakeLists.txt, once every target exists.
include(GNUInstallDirs)

# Everything `parallax` needs at run time is the executable: the modules are static libraries,
# shaders are compiled into it, and the shared libraries it links come from Debian packages
# (declared below). Documents go to share/doc/parallax.
install(TARGETS parallax RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The Python package installs itself (python/CMakeLists.txt: PARALLAX_PYTHON_INSTALL_DIR).
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}
        FILES_MATCHING PATTERN "*.md")

# --version: the version and the features of this build, one line each. A module adds its own
# with parallax_add_feature("...") (cmake/ParallaxTargets.cmake) from its CMakeLists.txt.
parallax_add_feature("rendering: OpenGL 4.5 core through libepoxy ${epoxy_VERSION}, headless "
                     "through EGL ${egl_VERSION} (surfaceless, or a GPU device)")
parallax_add_feature("viewer: GLFW ${glfw3_VERSION} window, Dear ImGui ${imgui_VERSION} panel")
parallax_add_feature("stereo: sbs, sbs-squeezed, tb, anaglyph, anaglyph-dubois, interlaced, "
                     "quad-buffer")
# The formats line is added by apps/parallax/command_line.cpp, from the format table.
parallax_add_feature("parallel: oneTBB ${TBB_VERSION}")
get_property(parallax_features GLOBAL PROPERTY PARALLAX_FEATURES)
set(PARALLAX_FEATURE_LINES "")
foreach(feature IN LISTS parallax_features)
  string(REPLACE "\\" "\\\\" feature "${feature}")
  string(REPLACE "\"" "\\\"" feature "${feature}")
  string(APPEND PARALLAX_FEATURE_LINES "  ${feature}\\n")
endforeach()
set(parallax_sanitizers "none")
if(PARALLAX_BUILD_FUZZ)
  set(parallax_sanitizers "address, undefined, fuzzer coverage")
elseif(PARALLAX_SANITIZE)
  set(parallax_sanitizers "address, undefined")
endif()
set(PARALLAX_BUILD_LINE "${CMAKE_BUILD_TYPE} build, ${CMAKE_CXX_COMPILER_ID} ${CMAKE_CXX_COMPILER_VERSION}, ${CMAKE_SYSTEM_PROCESSOR}, sanitizers: ${parallax_sanitizers}")
if(NOT CMAKE_BUILD_TYPE)
  set(PARALLAX_BUILD_LINE "unoptimised (no CMAKE_BUILD_TYPE) build, ${CMAKE_CXX_COMPILER_ID} ${CMAKE_CXX_COMPILER_VERSION}, ${CMAKE_SYSTEM_PROCESSOR}, sanitizers: ${parallax_sanitizers}")
endif()
configure_file(${PROJECT_SOURCE_DIR}/cmake/parallax_build_info.h.in
               ${PROJECT_BINARY_DIR}/generated/parallax_build_info.h @ONLY)
target_include_directories(parallax_cli PRIVATE ${PROJECT_BINARY_DIR}/generated)

# The Debian package. Its Depends are what dpkg-shlibdeps (Debian package dpkg-dev, with `file`)
# finds the executable linked against (libtbb12, libglfw3, libepoxy0, libstb0, libstdc++6, ...),
# plus what it loads without linking, which no tool can read off the binary: libepoxy opens
# libEGL.so.1 (libegl1) and libGL.so.1 (libgl1) with dlopen, and EGL opens Mesa's drivers
# (libgl1-mesa-dri, llvmpipe among them), which a headless `parallax render` needs on a machine
# without a GPU driver. tests/apps/check_install.sh checks that every library the executable
# needs belongs to a declared package.
set(CPACK_PACKAGE_NAME parallax)
set(CPACK_PACKAGE_VENDOR "The Parallax authors")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Viewer and toolkit for massive 3D point clouds")
string(CONCAT CPACK_PACKAGE_DESCRIPTION
       "Parallax reads PLY, LAS and text point clouds, builds level-of-detail octrees in the "
       "Potree 2.0 format out of core, and draws them with OpenGL 4.5 in a window or headless "
       "(EGL), in mono or off-axis stereo. The parallax command views, renders, inspects, "
       "converts, generates and benchmarks point files and octrees.")
set(CPACK_PACKAGE_CONTACT "Parallax maintainers <parallax@localhost>")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libegl1, libgl1, libgl1-mesa-dri")
if(PARALLAX_PYTHON_MODULE_BUILT)
  # The Python module (python/CMakeLists.txt) is built for one interpreter's ABI and imports
  # numpy at run time; neither is linked, so dpkg-shlibdeps cannot see them.
  string(APPEND CPACK_DEBIAN_PACKAGE_DEPENDS
         ", python3 (>= ${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}), "
         "python3 (<< ${Python3_VERSION_MAJOR}.${PARALLAX_PYTHON_NEXT_MINOR}), python3-numpy")
endif()
set(CPACK_GENERATOR DEB)
include(CPack)
