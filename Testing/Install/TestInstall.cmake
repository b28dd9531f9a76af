# SPDX-License-Identifier: BSD-3-Clause
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "failed (${result}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()

file(REMOVE_RECURSE "${PREFIX}" "${EXAMPLE_BUILD}")
run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${PREFIX}")
run(${CMAKE_COMMAND} -S "${EXAMPLE_SOURCE}" -B "${EXAMPLE_BUILD}" -G Ninja
  -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${PREFIX}")
run(${CMAKE_COMMAND} --build "${EXAMPLE_BUILD}")
run("${EXAMPLE_BUILD}/SphereCloud" --size 160 120 --output "${EXAMPLE_BUILD}/images")
if(PYTHON)
  run(${CMAKE_COMMAND} -E env "PYTHONPATH=${PREFIX}/${PYTHON_DESTINATION}"
    "${PYTHON}" -c "import sightline; m = sightline.vtkSightlineSphereMapper(); print('python', sightline.__version__, m.GetClassName())")
  # The installed command finds its package next to itself (no PYTHONPATH) and renders a
  # streamline file without a window.
  run(${CMAKE_COMMAND} -E env --unset=PYTHONPATH --unset=DISPLAY "${PREFIX}/bin/sightline-view"
    /usr/lib/python3/dist-packages/nibabel/tests/data/standard.trk
    --output "${EXAMPLE_BUILD}/images/sightline_view.png" --size 160 120)
  if(NOT EXISTS "${EXAMPLE_BUILD}/images/sightline_view.png")
    message(FATAL_ERROR "the installed sightline-view wrote no image")
  endif()
endif()
