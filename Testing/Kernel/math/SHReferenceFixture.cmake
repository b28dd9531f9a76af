# SPDX-License-Identifier: BSD-3-Clause
# Included by CTest after the discovered kernel tests (TEST_INCLUDE_FILES, see CMakeLists.txt):
# the tests that read the spherical-harmonics reference tables require the fixture that writes
# them (SphericalHarmonics.MakeReferences). SightlineKernelTests_TESTS is gtest_discover_tests'
# list of the discovered names.
foreach(sightline_test IN LISTS SightlineKernelTests_TESTS)
  if(sightline_test MATCHES "^SphericalHarmonicsReference\\.")
    set_tests_properties("${sightline_test}" PROPERTIES FIXTURES_REQUIRED sh_references)
  endif()
endforeach()
