# Every third-party package the build uses, found once. scripts/install_deps.sh installs them.
find_package(Threads REQUIRED)
find_package(OpenMP REQUIRED)                # MPM transfers; gcc's own libgomp
find_package(Protobuf REQUIRED)          # module mode: CONFIG mode is broken on Debian 12
find_package(gRPC CONFIG REQUIRED)
find_package(Eigen3 CONFIG REQUIRED)
find_package(urdfdom CONFIG REQUIRED)
find_package(nlohmann_json 3 CONFIG REQUIRED)
find_package(cppzmq CONFIG REQUIRED)
find_package(spdlog CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(OpenSSL REQUIRED)             # HMAC of snapshots

# Bullet in double precision: Debian ships -float64 builds; the define must match them.
find_path(BULLET_INCLUDE_DIR btBulletDynamicsCommon.h PATH_SUFFIXES bullet REQUIRED)
foreach(lib BulletDynamics BulletCollision LinearMath)
  find_library(BULLET_${lib}_LIBRARY ${lib}-float64 REQUIRED)
  list(APPEND BULLET_FLOAT64_LIBRARIES ${BULLET_${lib}_LIBRARY})
endforeach()
add_library(bullet_float64 INTERFACE)
target_include_directories(bullet_float64 SYSTEM INTERFACE ${BULLET_INCLUDE_DIR})
target_compile_definitions(bullet_float64 INTERFACE BT_USE_DOUBLE_PRECISION)
target_link_libraries(bullet_float64 INTERFACE ${BULLET_FLOAT64_LIBRARIES})

# Renderer: EGL + desktop OpenGL through libglvnd (CMake 3.25 has no GLES3 component).
set(OpenGL_GL_PREFERENCE GLVND)
find_package(OpenGL REQUIRED COMPONENTS OpenGL EGL)
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs videoio)
find_package(assimp CONFIG REQUIRED)
