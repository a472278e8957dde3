# Writes OUT (#define TB_GIT_COMMIT "<12 hex digits>[-modified]") at every build,
# touching it only when the text changes: run.json names the commit the binary was
# built from, not the one CMake was configured at. "-modified": the source (results,
# docs and Markdown aside) differs from that commit.
# Usage: cmake -DSOURCE_DIR=... -DOUT=... -P git_commit.cmake
execute_process(COMMAND git rev-parse --short=12 HEAD WORKING_DIRECTORY ${SOURCE_DIR}
  OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE failed)
if(failed OR NOT commit)
  set(commit unknown)
else()
  execute_process(COMMAND git diff --quiet HEAD -- . ":(exclude)results" ":(exclude)docs" ":(exclude)*.md"
    WORKING_DIRECTORY ${SOURCE_DIR} RESULT_VARIABLE modified ERROR_QUIET)
  if(modified)
    set(commit "${commit}-modified")
  endif()
endif()
set(text "#define TB_GIT_COMMIT \"${commit}\"\n")
set(old "")
if(EXISTS ${OUT})
  file(READ ${OUT} old)
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUT} "${text}")
endif()
