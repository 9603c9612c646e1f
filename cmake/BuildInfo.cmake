# Writes BuildInfo.cpp with the current git revision; run at every build (script mode), and the
# file is only rewritten when its content changes, so an unchanged revision rebuilds nothing.
execute_process(COMMAND git rev-parse --short HEAD WORKING_DIRECTORY ${SRC}
                OUTPUT_VARIABLE SPALL_GIT_REVISION OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT SPALL_GIT_REVISION)
  set(SPALL_GIT_REVISION "unknown")
else()
  execute_process(COMMAND git diff --quiet HEAD -- src include WORKING_DIRECTORY ${SRC}
                  RESULT_VARIABLE dirty ERROR_QUIET)
  if(dirty)
    set(SPALL_GIT_REVISION "${SPALL_GIT_REVISION}-dirty")
  endif()
endif()
configure_file(${SRC}/src/app/BuildInfo.cpp.in ${OUT} @ONLY)
