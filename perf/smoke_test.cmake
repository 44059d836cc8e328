# perf.bench_core_smoke: runs the sweep on tiny generated scenes into WORK_DIR and checks
# that every result file is there and that the CSV has a row per run.
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(
  COMMAND ${BENCH} --scenes cloth-ball,n-body,bart,skirt --size tiny --steps 2 --repeats 1 --threads 1,2
          --methods traverse,phc,fbd --cache ${WORK_DIR}/cache --out ${WORK_DIR}/results --machine smoke
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "bench_core exited with ${rc}")
endif()
foreach(f runs.csv results.md speedup.png stages.png volume_tests.png front_length.png fbd_phc_ratio.png
          front_memory.png elementary_per_contact.png)
  if(NOT EXISTS ${WORK_DIR}/results/${f})
    message(FATAL_ERROR "bench_core wrote no ${f}")
  endif()
endforeach()
# 4 scenes x (3 methods x 2 thread counts x (warm-up + 1 run) + 2 runs in the paper's setting
# + 3 work-and-span runs on 1 thread and 3 on 2), plus the header
file(STRINGS ${WORK_DIR}/results/runs.csv lines)
list(LENGTH lines n)
if(NOT n EQUAL 81)
  message(FATAL_ERROR "runs.csv has ${n} lines, expected 81")
endif()
file(STRINGS ${WORK_DIR}/results/runs.csv paper REGEX ",paper,")
list(LENGTH paper n)
if(NOT n EQUAL 8)
  message(FATAL_ERROR "runs.csv has ${n} runs in the paper's setting, expected 8")
endif()
file(STRINGS ${WORK_DIR}/results/runs.csv measured REGEX ",work-span,")
list(LENGTH measured n)
if(NOT n EQUAL 12)
  message(FATAL_ERROR "runs.csv has ${n} work-and-span runs, expected 12")
endif()
file(STRINGS ${WORK_DIR}/results/runs.csv measured REGEX ",work-span-2,[a-z]+,2,")
list(LENGTH measured n)
if(NOT n EQUAL 12)
  message(FATAL_ERROR "runs.csv has ${n} work-and-span runs on 2 threads, expected 12")
endif()
file(READ ${WORK_DIR}/results/results.md report)
if(NOT report MATCHES "## Work and span" OR NOT report MATCHES "predicted ms/frame"
   OR NOT report MATCHES "\\| work on 2 threads \\| 2 / 1 \\|")
  message(FATAL_ERROR "results.md has no work-and-span tables")
endif()
file(GLOB leftovers ${WORK_DIR}/results/*.tmp* ${WORK_DIR}/cache/*.tmp*)
if(leftovers)
  message(FATAL_ERROR "temporary files left behind: ${leftovers}")
endif()
