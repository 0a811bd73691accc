# cmake -DQRM=<qrm> -DWORK=<dir> -DCHECK_PNG=... -DCHECK_SVG=... -DPYTHON=... [-DQUICK=ON] -P check_figures.cmake
# README's first command, `qrm figures`: every file it promises exists; every PNG decodes with
# the independent decoder and is not blank; every SVG is well-formed XML.
file(REMOVE_RECURSE ${WORK})
set(flags --out ${WORK} --quiet)
if(QUICK)
  list(APPEND flags --quick)
endif()
execute_process(COMMAND ${QRM} figures ${flags} RESULT_VARIABLE rv OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rv EQUAL 0)
  message(FATAL_ERROR "qrm figures failed (${rv}):\n${out}\n${err}")
endif()
set(pngs paper_8x8_lightmap_estimated paper_8x8_lightmap_exact paper_8x8_lightmap_classical
         paper_8x8_lightmap_difference paper_8x8_lightmap_upsampled cornell_box_8_exact cornell_box_8_mc
         cornell_box_8_emulated cornell_box_8_quantum two_spheres_8_quantum two_spheres_8_exact two_spheres_8_mc two_spheres_8_emulated)
foreach(p ${pngs})
  execute_process(COMMAND ${PYTHON} ${CHECK_PNG} ${WORK}/${p}.png --require-nonblank RESULT_VARIABLE rv OUTPUT_VARIABLE o
                  ERROR_VARIABLE o)
  if(NOT rv EQUAL 0)
    message(FATAL_ERROR "${p}.png: ${o}")
  endif()
endforeach()
foreach(s convergence accuracy_time accuracy_calls)
  execute_process(COMMAND ${PYTHON} ${CHECK_SVG} ${WORK}/${s}.svg RESULT_VARIABLE rv OUTPUT_VARIABLE o ERROR_VARIABLE o)
  if(NOT rv EQUAL 0)
    message(FATAL_ERROR "${s}.svg: ${o}")
  endif()
endforeach()
foreach(f summary.md convergence.csv accuracy_time.csv mc_vs_exact.csv paper_8x8_lightmap.csv)
  if(NOT EXISTS ${WORK}/${f})
    message(FATAL_ERROR "qrm figures did not write ${f}")
  endif()
endforeach()
message(STATUS "qrm figures wrote every promised file; PNGs decode and are not blank")
