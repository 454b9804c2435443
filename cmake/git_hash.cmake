# Writes OUTPUT, a header defining HRIBENCH_GIT_HASH, from `git describe` of SOURCE_DIR. Runs at
# every build (not only at configure), and rewrites the header only when the hash changed, so
# results always record the commit that was built without rebuilding anything needlessly.
execute_process(COMMAND git describe --always --dirty --abbrev=12
                WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE hash OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT hash)
  set(hash "unknown")
endif()
set(content "#pragma once\n#define HRIBENCH_GIT_HASH \"${hash}\"\n")
set(old "")
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} old)
endif()
if(NOT old STREQUAL content)
  file(WRITE ${OUTPUT} "${content}")
endif()
