# SPDX-License-Identifier: BSD-3-Clause
# One way to add a GoogleTest executable to CTest: sources, libraries, compile definitions,
# labels and properties in one call, discovered test by test (gtest_discover_tests).
#
#   sightline_add_gtest(NAME target SOURCES ... [LIBRARIES ...] [DEFINITIONS ...]
#     [LABEL label] [PROPERTIES key value ...] [AUTOINIT vtk-modules...] [NO_PRETTY_VALUES])
#
# One label per executable: gtest_discover_tests writes the properties of each test as a flat
# argument list, so a second label would be read as a property name and every property after
# it (FIXTURES_REQUIRED, TIMEOUT) would be lost.
#
# AUTOINIT registers VTK object factories (rendering backends) for tests that open windows.
include(GoogleTest)

function(sightline_add_gtest)
  cmake_parse_arguments(PARSE_ARGV 0 arg "NO_PRETTY_VALUES" "NAME;LABEL"
    "SOURCES;LIBRARIES;DEFINITIONS;PROPERTIES;AUTOINIT")
  if(NOT arg_NAME OR NOT arg_SOURCES)
    message(FATAL_ERROR "sightline_add_gtest needs NAME and SOURCES")
  endif()
  add_executable(${arg_NAME} ${arg_SOURCES})
  target_link_libraries(${arg_NAME} PRIVATE ${arg_LIBRARIES} GTest::gtest_main)
  target_compile_features(${arg_NAME} PRIVATE cxx_std_17)
  target_compile_options(${arg_NAME} PRIVATE -Wall -Wextra)
  target_compile_definitions(${arg_NAME} PRIVATE ${arg_DEFINITIONS})
  if(arg_AUTOINIT)
    vtk_module_autoinit(TARGETS ${arg_NAME} MODULES ${arg_AUTOINIT})
  endif()
  set(pretty)
  if(arg_NO_PRETTY_VALUES)
    set(pretty NO_PRETTY_VALUES)
  endif()
  gtest_discover_tests(${arg_NAME} ${pretty}
    PROPERTIES LABELS ${arg_LABEL} ${arg_PROPERTIES}
    DISCOVERY_TIMEOUT 60)
endfunction()
