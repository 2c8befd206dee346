# Run at every build (cmake -P): writes OUTPUT, a source file naming the commit the build was made from,
# and touches it only when that changes, so an unchanged tree rebuilds nothing.
#   -DSOURCE_DIR=<project root> -DOUTPUT=<generated .cpp> -DVERSION=<project version>
find_package(Git QUIET)
set(commit "unknown (not built from a git checkout)")
if(GIT_FOUND)
  execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SOURCE_DIR} describe --always --dirty=-modified --abbrev=12
                  OUTPUT_VARIABLE described OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE failed
                  ERROR_QUIET)
  if(NOT failed AND described)
    set(commit ${described})
  endif()
endif()
file(WRITE ${OUTPUT}.new
     "// Generated at build time by base/build_info.cmake.\n#include \"base/build_info.hpp\"\n\n"
     "namespace ibvalve::base {\n"
     "const char* version() { return \"${VERSION}\"; }\n"
     "const char* commit() { return \"${commit}\"; }\n"
     "} // namespace ibvalve::base\n")
file(COPY_FILE ${OUTPUT}.new ${OUTPUT} ONLY_IF_DIFFERENT)
file(REMOVE ${OUTPUT}.new)
