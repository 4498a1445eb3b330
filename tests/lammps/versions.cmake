# ctest label lammps_versions: the LAMMPS checks against each further LAMMPS build of
# HS_LAMMPS_ROOT (plugin/CMakeLists.txt), its stock lmp loading build/lammps-DATE/hardsphereplugin.so
# with `plugin load` (the runner's --plugin). One test per feature, serial and on 2 ranks:
# lammps_vDATE_FEATURE_serial | _mpi2. The LAMMPS `python` command finds its module in the
# build's source tree (build_lammps.sh keeps source/python beside the prefix).
include(${CMAKE_CURRENT_LIST_DIR}/features.cmake)
foreach(_entry ${HS_LAMMPS_PLUGINS})
  string(REPLACE "|" ";" _parts "${_entry}")
  list(GET _parts 0 _version)
  list(GET _parts 1 _lmp)
  list(GET _parts 2 _plugin)
  get_filename_component(_prefix "${_lmp}" DIRECTORY)
  get_filename_component(_python "${_prefix}/../../source/python" ABSOLUTE)
  set(_env "PYTHONPATH=${PROJECT_SOURCE_DIR}:${_python}")
  set(_args --lmp ${_lmp} --plugin ${_plugin} --hs $<TARGET_FILE:hardsphere>)
  foreach(_feature_entry ${HS_LAMMPS_FEATURES})
    string(REGEX REPLACE ":.*" "" _feature ${_feature_entry})
    set(_name lammps_v${_version}_${_feature})
    add_test(NAME ${_name}_serial COMMAND ${Python3_EXECUTABLE} -m tests.lammps.${_feature} ${_args})
    set_tests_properties(${_name}_serial PROPERTIES LABELS lammps_versions TIMEOUT 900 ENVIRONMENT "${_env}")
    if(MPIEXEC_EXECUTABLE)
      add_test(NAME ${_name}_mpi2 COMMAND ${Python3_EXECUTABLE} -m tests.lammps.${_feature} ${_args} --np 2
                                          --mpirun ${MPIEXEC_EXECUTABLE})
      set_tests_properties(${_name}_mpi2 PROPERTIES LABELS "lammps_versions;mpi" TIMEOUT 900 PROCESSORS 2
                           ENVIRONMENT "${_env}")
    endif()
  endforeach()
  # The reference inputs (the converted DEM scenes among them) on this release's stock lmp.
  add_test(NAME lammps_v${_version}_reference_inputs
           COMMAND ${Python3_EXECUTABLE} -m tests.lammps.run_reference_inputs --lmp ${_lmp} --plugin ${_plugin}
                   --inputs ${PROJECT_SOURCE_DIR}/reference_inputs/lammps)
  set_tests_properties(lammps_v${_version}_reference_inputs PROPERTIES LABELS lammps_versions TIMEOUT 300
                       ENVIRONMENT "${_env}")
  # lmp_hs (Debian's LAMMPS) with this release's liblammps.so.0 first on LD_LIBRARY_PATH: refused
  # with a message naming both releases, on 1 and 2 ranks.
  if(TARGET lmp_hs)
    get_filename_component(_libdir "${_prefix}/../lib" ABSOLUTE)
    add_test(NAME lammps_v${_version}_lmp_hs_library
             COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_LIST_DIR}/library_check.py $<TARGET_FILE:lmp_hs> ${_libdir}
                     ${_version} ${MPIEXEC_EXECUTABLE})
    set_tests_properties(lammps_v${_version}_lmp_hs_library PROPERTIES LABELS lammps_versions TIMEOUT 300
                         PROCESSORS 2)
  endif()
  if(MPIEXEC_EXECUTABLE)
    add_test(NAME lammps_v${_version}_decompositions_mpi
             COMMAND ${Python3_EXECUTABLE} -m tests.lammps.decompositions ${_args} --mpirun ${MPIEXEC_EXECUTABLE})
    set_tests_properties(lammps_v${_version}_decompositions_mpi PROPERTIES LABELS "lammps_versions;mpi" TIMEOUT 900
                         PROCESSORS 2 ENVIRONMENT "${_env}")
  endif()
endforeach()
