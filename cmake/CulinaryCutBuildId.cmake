# The git commit the binaries are built from, reported by GetServerInfo. A build without the git history
# (a container image: .dockerignore leaves .git out) passes it in: -DCULINARYCUT_BUILD_ID=... or the
# environment variable CULINARYCUT_BUILD_ID (the Dockerfile's build argument).
if(NOT CULINARYCUT_BUILD_ID AND NOT "$ENV{CULINARYCUT_BUILD_ID}" STREQUAL "")
  set(CULINARYCUT_BUILD_ID "$ENV{CULINARYCUT_BUILD_ID}")
endif()
if(NOT CULINARYCUT_BUILD_ID)
  execute_process(
    COMMAND git rev-parse --short=12 HEAD
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}
    OUTPUT_VARIABLE CULINARYCUT_BUILD_ID
    OUTPUT_STRIP_TRAILING_WHITESPACE
    ERROR_QUIET)
endif()
if(NOT CULINARYCUT_BUILD_ID)
  set(CULINARYCUT_BUILD_ID "unknown")
endif()
