# Warnings and sanitizers are applied per target through this interface library, never globally.
add_library(parallax_build_flags INTERFACE)
target_compile_features(parallax_build_flags INTERFACE cxx_std_20)
target_compile_options(parallax_build_flags INTERFACE -Wall -Wextra -Wpedantic -Wshadow
                                                       -Wno-missing-field-initializers)
if(PARALLAX_WERROR)
  target_compile_options(parallax_build_flags INTERFACE -Werror)
endif()
if(PARALLAX_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  # In a unity batch every source is an included file, and GCC then takes a class whose member
  # has a type of the source's anonymous namespace for one in a header that several units share
  # (-Wsubobject-linkage); within one batch that cannot happen.
  target_compile_options(parallax_build_flags INTERFACE -Wno-subobject-linkage)
endif()
if(PARALLAX_BUILD_FUZZ AND NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "PARALLAX_BUILD_FUZZ needs clang (libFuzzer): configure with "
                      "-DCMAKE_CXX_COMPILER=clang++ (Debian packages 'clang', "
                      "'libclang-rt-14-dev')")
endif()
# A fuzzing tree is a sanitizer tree: the fuzz targets are built beside the tests, in the same
# tree (scripts/test.sh builds them in its sanitizer tree), and only the modules they read get
# libFuzzer's coverage instrumentation on top (fuzz/CMakeLists.txt, PARALLAX_FUZZED_MODULES).
if(PARALLAX_SANITIZE OR PARALLAX_BUILD_FUZZ)
  target_compile_options(parallax_build_flags INTERFACE -fsanitize=address,undefined
                                                         -fno-sanitize-recover=undefined
                                                         -fno-omit-frame-pointer)
  target_link_options(parallax_build_flags INTERFACE -fsanitize=address,undefined)
  # Executables not position independent: an instrumented executable's data is mostly pointers
  # (ASan's and UBSan's descriptors), and as PIE the loader relocated about two million of them
  # at every start, 0.2 s of CPU of each test process and each `parallax` a test runs (the
  # `parallax` executable: 0.70 s of CPU to print its version as PIE, 0.52 s without). Release
  # builds stay PIE, as Debian builds them.
  target_link_options(parallax_build_flags INTERFACE
                      $<$<STREQUAL:$<TARGET_PROPERTY:TYPE>,EXECUTABLE>:-no-pie>)
endif()
add_library(parallax::build_flags ALIAS parallax_build_flags)

# parallax_add_module(NAME SOURCES... DEPENDS targets...) declares one module library
# `parallax_NAME` with the alias `parallax::NAME`; headers are included as "NAME/file.h".
function(parallax_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS;PRIVATE_DEPENDS" ${ARGN})
  add_library(parallax_${name} STATIC ${ARG_SOURCES})
  add_library(parallax::${name} ALIAS parallax_${name})
  target_include_directories(parallax_${name} PUBLIC ${PROJECT_SOURCE_DIR}/src)
  target_link_libraries(parallax_${name} PUBLIC ${ARG_DEPENDS} PRIVATE parallax::build_flags
                                                                     ${ARG_PRIVATE_DEPENDS})
  target_compile_features(parallax_${name} PUBLIC cxx_std_20)
  if(PARALLAX_BUILD_PYTHON)
    # The Python module (python/) is a shared object that links these static libraries: their
    # code must be position independent (-fPIC; the default -fPIE has TLS and relocation models
    # a shared object cannot use). It costs nothing measurable on x86-64.
    set_target_properties(parallax_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  endif()
endfunction()

# parallax_add_feature(TEXT...) adds a line to what `parallax --version` lists as this build's
# features (cmake/ParallaxPackaging.cmake writes them out); the pieces of TEXT are joined. No
# semicolons in TEXT: CMake reads them as list separators.
function(parallax_add_feature)
  string(JOIN "" text ${ARGN})
  set_property(GLOBAL APPEND PROPERTY PARALLAX_FEATURES "${text}")
endfunction()
