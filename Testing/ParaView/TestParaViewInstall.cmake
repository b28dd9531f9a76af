# SPDX-License-Identifier: BSD-3-Clause
# ParaView.Install: `cmake --install` of the ParaView configuration into a scratch prefix, then
# pvbatch loads the installed plugin from PV_PLUGIN_PATH (only the prefix's plugin folder) with
# no LD_LIBRARY_PATH and no build-tree PYTHONPATH, and renders a Sightline representation
# (install_render.py asserts that every Sightline library it mapped comes from the prefix).
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "failed (${result}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}${err}")
  # pvbatch returns 0 after errors reported through VTK's output window: they fail the test too.
  if(err MATCHES "ERR\\||ERROR:")
    message(FATAL_ERROR "errors reported: ${ARGN}\n${err}")
  endif()
endfunction()

file(REMOVE_RECURSE "${PREFIX}")
run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${PREFIX}")
set(plugin_dir "${PREFIX}/${LIBDIR}/paraview-${PARAVIEW_VERSION}/plugins/Sightline")
if(NOT EXISTS "${plugin_dir}/Sightline.so")
  message(FATAL_ERROR "no ${plugin_dir}/Sightline.so after cmake --install")
endif()
run(${CMAKE_COMMAND} -E env --unset=LD_LIBRARY_PATH "PV_PLUGIN_PATH=${plugin_dir}"
  "PYTHONPATH=${PARAVIEW_PYTHONPATH}"
  "${PVBATCH}" --force-offscreen-rendering "${SCRIPT}" "${PREFIX}" "${SWC}")
