# Warnings and sanitizers are applied per target through this interface library, never globally.
add_library(parallax_build_flags INTERFACE)
target_compile_features(parallax_build_flags INTERFACE cxx_std_20)
target_compile_options(parallax_build_flags INTERFACE -Wall -Wextra -Wpedantic -Wshadow
                                                       -Wno-missing-field-initializers)
if(PARALLAX_SANITIZE)
  target_compile_options(parallax_build_flags INTERFACE -fsanitize=address,undefined
                                                         -fno-sanitize-recover=undefined
                                                         -fno-omit-frame-pointer)
  target_link_options(parallax_build_flags INTERFACE -fsanitize=address,undefined)
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
endfunction()
