# Regenerates version.hpp with the current git SHA (and "-dirty" for uncommitted
# changes). configure_file rewrites the header only when its content changes, so
# an unchanged tree recompiles nothing.
execute_process(COMMAND git rev-parse --short=12 HEAD WORKING_DIRECTORY ${SRC}
                OUTPUT_VARIABLE NARWHAL_GIT_SHA OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT NARWHAL_GIT_SHA)
  set(NARWHAL_GIT_SHA "unknown")
else()
  execute_process(COMMAND git status --porcelain --untracked-files=no WORKING_DIRECTORY ${SRC}
                  OUTPUT_VARIABLE dirty OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(dirty)
    set(NARWHAL_GIT_SHA "${NARWHAL_GIT_SHA}-dirty")
  endif()
endif()
configure_file(${SRC}/solver/core/version.hpp.in ${OUT} @ONLY)
