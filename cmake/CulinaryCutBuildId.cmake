# The git commit the binaries are built from, reported by GetServerInfo.
execute_process(
  COMMAND git rev-parse --short=12 HEAD
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}
  OUTPUT_VARIABLE CULINARYCUT_BUILD_ID
  OUTPUT_STRIP_TRAILING_WHITESPACE
  ERROR_QUIET)
if(NOT CULINARYCUT_BUILD_ID)
  set(CULINARYCUT_BUILD_ID "unknown")
endif()
