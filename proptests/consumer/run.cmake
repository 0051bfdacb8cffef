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
# The corpus is installed and the installed dcad reads it there (issue 47), not the build machine's checkout: a case
# added to the installed copy only is listed.
if(EXE STREQUAL "consumer")
  configure_file(${WORK}/prefix/share/dcad/cases/lc-4port.cir ${WORK}/prefix/share/dcad/cases/only-installed.cir COPYONLY)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=DCAD_CASES ${WORK}/prefix/bin/dcad cases list
                  RESULT_VARIABLE rc OUTPUT_VARIABLE listed)
  if(NOT rc EQUAL 0 OR NOT listed MATCHES "only-installed")
    message(FATAL_ERROR "install_consumer: the installed dcad does not read PREFIX/share/dcad/cases (${rc}): ${listed}")
  endif()
endif()
