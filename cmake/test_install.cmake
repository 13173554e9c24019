# Installs the build into PREFIX (emptied first), then configures, builds and runs the consumer
# project CONSUMER_DIR against it: what a user's find_package(trident) does.
# cmake -DBUILD_DIR=... -DPREFIX=... -DCONSUMER_DIR=... -DGENERATOR=... -P test_install.cmake
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "failed (${status}): ${ARGN}")
  endif()
endfunction()

file(REMOVE_RECURSE ${PREFIX})
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX}/usr)
run(${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${PREFIX}/consumer-build -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_PREFIX_PATH=${PREFIX}/usr)
run(${CMAKE_COMMAND} --build ${PREFIX}/consumer-build)
run(${PREFIX}/consumer-build/trace_teapot)
