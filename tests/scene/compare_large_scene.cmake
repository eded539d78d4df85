# Regenerates the large scene into OUT and compares it with the committed files in SCENES.
execute_process(COMMAND ${PYTHON} ${SCRIPT} --out-dir ${OUT} RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "make-large-scene.py failed: ${status}")
endif()
foreach(file large.yaml meshes/large-rock.obj)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}/${file} ${SCENES}/${file}
                  RESULT_VARIABLE differs)
  if(NOT differs EQUAL 0)
    message(FATAL_ERROR "${file} differs from what scripts/make-large-scene.py writes")
  endif()
endforeach()
