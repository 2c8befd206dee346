# ibvalve_add_test(NAME <name> SOURCES <files...> LIBS <targets...> LABELS <labels...> [RANKS <n>])
#
# Builds a GoogleTest program whose main initialises MPI and PETSc (tests/support/test_main.cpp) and
# registers it with CTest. RANKS > 1 runs it under mpiexec; the test then also carries the label
# `mpi`. Under root Open MPI refuses to start unless told, so the environment says so, and
# --oversubscribe lets 2 ranks start on any machine.
set(IBVALVE_TEST_ENVIRONMENT
    OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
    OMPI_MCA_btl_vader_single_copy_mechanism=none)

function(ibvalve_add_test)
  cmake_parse_arguments(T "" "NAME;RANKS;TIMEOUT" "SOURCES;LIBS;LABELS;ARGS" ${ARGN})
  if(NOT T_RANKS)
    set(T_RANKS 1)
  endif()
  if(NOT TARGET ${T_NAME})
    add_executable(${T_NAME} ${T_SOURCES})
    target_link_libraries(${T_NAME} PRIVATE ibvalve_test_main ${T_LIBS})
  endif()
  set(labels ${T_LABELS})
  if(T_RANKS GREATER 1)
    list(APPEND labels mpi)
    set(test_name ${T_NAME}_np${T_RANKS})
  else()
    set(test_name ${T_NAME})
  endif()
  add_test(NAME ${test_name}
           COMMAND ${MPIEXEC_PROGRAM} --oversubscribe -n ${T_RANKS} $<TARGET_FILE:${T_NAME}> ${T_ARGS}
           WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
  list(REMOVE_DUPLICATES labels)
  set_tests_properties(${test_name} PROPERTIES LABELS "${labels}" PROCESSORS ${T_RANKS}
                       ENVIRONMENT "${IBVALVE_TEST_ENVIRONMENT}")
  if(T_TIMEOUT)
    set_tests_properties(${test_name} PROPERTIES TIMEOUT ${T_TIMEOUT})
  endif()
endfunction()

# ibvalve_add_cli_test(NAME <name> COMMAND <args...> LABELS <labels...> [RANKS n] [WILL_FAIL] [PASS_REGEX r])
# Runs the ibvalve program itself (under mpiexec) as a test.
function(ibvalve_add_cli_test)
  cmake_parse_arguments(T "WILL_FAIL" "NAME;RANKS;PASS_REGEX" "COMMAND;LABELS" ${ARGN})
  if(NOT T_RANKS)
    set(T_RANKS 1)
  endif()
  set(labels ${T_LABELS})
  if(T_RANKS GREATER 1)
    list(APPEND labels mpi)
  endif()
  add_test(NAME ${T_NAME}
           COMMAND ${MPIEXEC_PROGRAM} --oversubscribe -n ${T_RANKS} $<TARGET_FILE:ibvalve> ${T_COMMAND}
           WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
  set_tests_properties(${T_NAME} PROPERTIES LABELS "${labels}" PROCESSORS ${T_RANKS}
                       ENVIRONMENT "${IBVALVE_TEST_ENVIRONMENT}")
  if(T_WILL_FAIL)
    set_tests_properties(${T_NAME} PROPERTIES WILL_FAIL TRUE)
  endif()
  if(T_PASS_REGEX)
    set_tests_properties(${T_NAME} PROPERTIES PASS_REGULAR_EXPRESSION "${T_PASS_REGEX}")
  endif()
endfunction()
