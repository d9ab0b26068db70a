# Helper: a PETSc test program. fdem_add_petsc_test(NAME name SOURCE file [SOURCES more]
#   [RANKS 1 2] [ARGS ...]) registers one CTest test per rank count.
function(fdem_add_petsc_test)
  cmake_parse_arguments(T "" "NAME;SOURCE" "RANKS;ARGS;LABELS;SOURCES" ${ARGN})
  if(NOT TARGET ${T_NAME})
    add_executable(${T_NAME} ${T_SOURCE} ${T_SOURCES})
    target_link_libraries(${T_NAME} fdem m)
  endif()
  if(NOT T_RANKS)
    set(T_RANKS 1)
  endif()
  foreach(n ${T_RANKS})
    set(tname ${T_NAME}_np${n})
    if(T_ARGS)
      string(MD5 h "${T_ARGS}")
      string(SUBSTRING ${h} 0 6 h)
      set(tname ${T_NAME}_${h}_np${n})
    endif()
    add_test(NAME ${tname}
      COMMAND ${FDEM_MPIEXEC} ${FDEM_MPIEXEC_FLAGS} -n ${n} $<TARGET_FILE:${T_NAME}> ${T_ARGS})
    set_tests_properties(${tname} PROPERTIES TIMEOUT 600 LABELS "${T_LABELS}"
      ENVIRONMENT "OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMPI_MCA_rmaps_base_oversubscribe=1")
  endforeach()
endfunction()
