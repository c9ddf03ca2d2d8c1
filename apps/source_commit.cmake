# SPDX-License-Identifier: Apache-2.0
# Writes OUTPUT: `#define MORPHMILL_SOURCE_COMMIT "<commit>"`, the git commit of SOURCE_DIR with
# "-modified" when tracked files differ from it, or "unknown" outside a git checkout (or without
# git); and `#define MORPHMILL_GIT_DESCRIBE "<git describe --always --dirty --tags>"` ("" without git). Run at every build (not at configure time) so a new commit is never reported as an old
# one; the header is replaced only when the text changes, so nothing recompiles otherwise.
set(commit "unknown")
set(described "")
find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SOURCE_DIR} rev-parse --verify HEAD
                  OUTPUT_VARIABLE head RESULT_VARIABLE head_status
                  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(head_status EQUAL 0 AND head)
    set(commit "${head}")
    execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SOURCE_DIR} status --porcelain --untracked-files=no
                    OUTPUT_VARIABLE changes RESULT_VARIABLE status_status ERROR_QUIET)
    if(NOT status_status EQUAL 0 OR changes)
      set(commit "${commit}-modified")
    endif()
    execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SOURCE_DIR} describe --always --dirty --tags
                    OUTPUT_VARIABLE described OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  endif()
endif()
file(WRITE "${OUTPUT}.new" "#define MORPHMILL_SOURCE_COMMIT \"${commit}\"\n"
                          "#define MORPHMILL_GIT_DESCRIBE \"${described}\"\n")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different "${OUTPUT}.new" "${OUTPUT}")
file(REMOVE "${OUTPUT}.new")
