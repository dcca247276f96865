# Runs raymappers-bench and fails unless it exits with 0 (it measured rows) and its output
# matches every regular expression of EXPECT (a list); for the Bench.* tests.
# usage: cmake -DBENCH=path -DARGS=a;b;c -DEXPECT=re1;re2 -P RunBenchCheck.cmake
execute_process(COMMAND "${BENCH}" ${ARGS} RESULT_VARIABLE rc OUTPUT_VARIABLE out
  ERROR_VARIABLE err)
message("${out}${err}")
if (NOT rc EQUAL 0)
  message(FATAL_ERROR "raymappers-bench exited with ${rc}: no rows measured")
endif ()
foreach (expected IN LISTS EXPECT)
  if (NOT "${out}${err}" MATCHES "${expected}")
    message(FATAL_ERROR "raymappers-bench's output lacks \"${expected}\"")
  endif ()
endforeach ()
