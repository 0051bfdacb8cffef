# ctest `install_consumer`: install this build into a fresh prefix, then configure, build and run
# proptests/consumer (a project that only knows find_package(dcad CONFIG)).  -DBUILD= -DSRC= -DWORK=
# [-DEXE=consumer] [-DHIDE=Pkg,Pkg] (packages hidden from the consumer's CMake)
file(REMOVE_RECURSE ${WORK})
if(NOT EXE)
  set(EXE consumer)
endif()
set(hidden "")
string(REPLACE "," ";" HIDE "${HIDE}")
foreach(p IN LISTS HIDE)
  list(APPEND hidden "-DCMAKE_DISABLE_FIND_PACKAGE_${p}=ON")
endforeach()
foreach(step
    "${CMAKE_COMMAND};--install;${BUILD};--prefix;${WORK}/prefix"
    "${CMAKE_COMMAND};-S;${SRC};-B;${WORK}/build;-DCMAKE_BUILD_TYPE=Release;-DCMAKE_PREFIX_PATH=${WORK}/prefix;${hidden}"
    "${CMAKE_COMMAND};--build;${WORK}/build"
    "${WORK}/build/${EXE};--gtest_brief=1")
  execute_process(COMMAND ${step} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install_consumer: '${step}' failed (${rc})")
  endif()
endforeach()
