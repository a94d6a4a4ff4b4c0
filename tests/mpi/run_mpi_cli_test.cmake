# tests/mpi/run_mpi_cli_test.cmake — `mpirun -np N vcmm …` against the plain `vcmm` (docs/mpi.md):
# the outputs must be byte-identical but for the fields that say how the run was spread or how
# long it took. Run by CTest (tests/CMakeLists.txt) only when MPI was found:
#   cmake -DMODE=uncertainty|validate|demo|bad_input -DVCMM=<plain vcmm> -DMPIEXEC=<mpirun>
#         -DSOURCE_DIR=<repo> -DWORK_DIR=<scratch> [-DWORLD=<demo world>] -P run_mpi_cli_test.cmake
# `VCMM` is the plain (static) command: under mpirun it hands over to vcmm-mpi beside it, so
# the hand-over is tested too. Each mode takes a few seconds on the 2-core test machine.
cmake_minimum_required(VERSION 3.22)
foreach(v MODE VCMM MPIEXEC SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run_mpi_cli_test.cmake: -D${v}=… is required")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
# Two ranks on one machine, as root in a container: oversubscribe the cores, and copy shared
# memory in and out (no cross-memory attach, which containers may forbid).
set(ENV{OMPI_ALLOW_RUN_AS_ROOT} 1)
set(ENV{OMPI_ALLOW_RUN_AS_ROOT_CONFIRM} 1)
set(ENV{OMPI_MCA_btl_vader_single_copy_mechanism} none)
set(mpirun "${MPIEXEC}" --oversubscribe)
set(model "${SOURCE_DIR}/examples/cmm_model.json")

# Runs a command in `dir` (made if needed), stdout to `out`; fails the test unless it exits 0.
function(run_ok dir out)
  file(MAKE_DIRECTORY "${dir}")
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY "${dir}" OUTPUT_FILE "${out}"
                  ERROR_VARIABLE err RESULT_VARIABLE rc TIMEOUT 120)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " cmd "${ARGN}")
    message(FATAL_ERROR "exit ${rc}: ${cmd}\n${err}")
  endif()
endfunction()

# `file` as text, without the lines naming fields that legitimately differ between runs (and
# those in extra_fields, "|name|name").
set(extra_fields "")
function(read_comparable file var)
  file(READ "${file}" text)
  string(REGEX REPLACE "\n[ ]*\"(wall_seconds[a-z_]*|ranks|threads|command${extra_fields})\": [^\n]*"
         "" text "${text}")
  # Paths into the run's own directory (the demo's world is inside its output directory).
  foreach(run plain np2)
    string(REPLACE "${WORK_DIR}/${run}/" "<run>/" text "${text}")
  endforeach()
  set(${var} "${text}" PARENT_SCOPE)
endfunction()

function(expect_same_file a b)
  read_comparable("${a}" ta)
  read_comparable("${b}" tb)
  if(NOT ta STREQUAL tb)
    execute_process(COMMAND diff "${a}" "${b}" OUTPUT_VARIABLE d)
    message(FATAL_ERROR "differ beyond ranks/threads/timing: ${a} ${b}\n${d}")
  endif()
endfunction()

# Every file under `a` is under `b` with the same (comparable) content, and vice versa.
function(expect_same_tree a b)
  file(GLOB_RECURSE fa RELATIVE "${a}" "${a}/*")
  file(GLOB_RECURSE fb RELATIVE "${b}" "${b}/*")
  list(SORT fa)
  list(SORT fb)
  if(NOT fa STREQUAL fb)
    message(FATAL_ERROR "the output directories hold different files:\n${a}: ${fa}\n${b}: ${fb}")
  endif()
  list(LENGTH fa n)
  if(n EQUAL 0)
    message(FATAL_ERROR "no files in ${a}")
  endif()
  foreach(f IN LISTS fa)
    expect_same_file("${a}/${f}" "${b}/${f}")
  endforeach()
  message(STATUS "${n} files identical in ${a} and ${b}")
endfunction()

function(expect_ranks file n)
  file(READ "${file}" text)
  if(NOT text MATCHES "\"ranks\": ${n}[,\n]")
    message(FATAL_ERROR "${file} does not record \"ranks\": ${n}")
  endif()
endfunction()

if(MODE STREQUAL "uncertainty")
  # A scanning measurement of the 171 mm ring; the default shrinkage treatment (three runs)
  # plus the uncertainty budget (a run per source), so every run_monte_carlo call is spread.
  run_ok("${WORK_DIR}" "${WORK_DIR}/simulate.out" "${VCMM}" simulate --model "${model}" --ring 171
         --points 720 --location 300,300,200 -o scan.csv)
  set(args uncertainty --model "${model}" --points "${WORK_DIR}/scan.csv" --trials 600
           --pilot-trials 100 --budget --budget-trials 200 --json)
  run_ok("${WORK_DIR}" "${WORK_DIR}/plain.json" "${VCMM}" ${args} --threads 2)
  # One process: `vcmm` runs as itself; `vcmm-mpi` initialises MPI for a job of one.
  get_filename_component(bin "${VCMM}" DIRECTORY)
  run_ok("${WORK_DIR}" "${WORK_DIR}/np1.json" ${mpirun} -np 1 "${bin}/vcmm-mpi" ${args} --threads 2)
  run_ok("${WORK_DIR}" "${WORK_DIR}/np2.json" ${mpirun} -np 2 "${VCMM}" ${args} --threads 1)
  expect_same_file("${WORK_DIR}/plain.json" "${WORK_DIR}/np1.json")
  expect_same_file("${WORK_DIR}/plain.json" "${WORK_DIR}/np2.json")
  expect_ranks("${WORK_DIR}/plain.json" 1)
  expect_ranks("${WORK_DIR}/np2.json" 2)
  # The adaptive procedure: the same blocks and stop decision.
  set(adaptive uncertainty --model "${model}" --points "${WORK_DIR}/scan.csv" --adaptive 2
               --reference LS --bias-treatment paper --json)
  run_ok("${WORK_DIR}" "${WORK_DIR}/plain_adaptive.json" "${VCMM}" ${adaptive} --threads 1)
  run_ok("${WORK_DIR}" "${WORK_DIR}/np2_adaptive.json" ${mpirun} -np 2 "${VCMM}" ${adaptive}
         --threads 1)
  expect_same_file("${WORK_DIR}/plain_adaptive.json" "${WORK_DIR}/np2_adaptive.json")
  # -o and --samples: written once, by rank 0, the same files.
  set(files uncertainty --model "${model}" --points "${WORK_DIR}/scan.csv" --trials 300
            --reference LS --bias-treatment paper --threads 1 -o report.txt --samples samples.csv)
  run_ok("${WORK_DIR}/files_plain" "${WORK_DIR}/files_plain.out" "${VCMM}" ${files})
  run_ok("${WORK_DIR}/files_np2" "${WORK_DIR}/files_np2.out" ${mpirun} -np 2 "${VCMM}" ${files})
  file(READ "${WORK_DIR}/files_np2.out" stdout_np2)
  if(NOT stdout_np2 STREQUAL "")
    message(FATAL_ERROR "with -o, nothing belongs on stdout; got:\n${stdout_np2}")
  endif()
  expect_same_file("${WORK_DIR}/files_plain/samples.csv" "${WORK_DIR}/files_np2/samples.csv")
elseif(MODE STREQUAL "demo")
  # The synthetic world (written by rank 0, read by both) and its 66-measurement campaign.
  set(args demo -o out --trials 100 --reference LS --bias-treatment paper --threads 1)
  run_ok("${WORK_DIR}/plain" "${WORK_DIR}/plain.out" "${VCMM}" ${args})
  run_ok("${WORK_DIR}/np2" "${WORK_DIR}/np2.out" ${mpirun} -np 2 "${VCMM}" ${args})
  expect_same_tree("${WORK_DIR}/plain/out" "${WORK_DIR}/np2/out")
  expect_ranks("${WORK_DIR}/np2/out/run_info.json" 2)
elseif(MODE STREQUAL "validate")
  # A campaign of the first 6 measurements of the world the plain run of MODE=demo wrote
  # (-DWORLD=…/world, a CTest fixture).
  if(NOT DEFINED WORLD OR NOT EXISTS "${WORLD}/campaign.json")
    message(FATAL_ERROR "MODE=validate needs -DWORLD=<the demo's world directory>; got '${WORLD}'")
  endif()
  file(READ "${WORLD}/campaign.json" campaign)
  string(JSON count LENGTH "${campaign}" measurements)
  foreach(i RANGE ${count})
    if(i GREATER_EQUAL 6 AND i LESS count)
      string(JSON campaign REMOVE "${campaign}" measurements 6)
    endif()
  endforeach()
  file(WRITE "${WORLD}/small.json" "${campaign}")  # beside it: its paths are relative
  set(args validate "${WORLD}/small.json" -o out --threads 1)
  run_ok("${WORK_DIR}/plain" "${WORK_DIR}/plain.out" "${VCMM}" ${args})
  run_ok("${WORK_DIR}/np2" "${WORK_DIR}/np2.out" ${mpirun} -np 2 "${VCMM}" ${args})
  expect_same_tree("${WORK_DIR}/plain/out" "${WORK_DIR}/np2/out")
  expect_ranks("${WORK_DIR}/np2/out/run_info.json" 2)
  # Resume under mpirun: rank 0 finds every measurement done, both ranks skip them alike.
  run_ok("${WORK_DIR}/np2" "${WORK_DIR}/np2_again.out" ${mpirun} -np 2 "${VCMM}" ${args})
  file(READ "${WORK_DIR}/np2_again.out" again)
  if(NOT again MATCHES "6 measurements \\(0 computed, 6 resumed\\)")
    message(FATAL_ERROR "the rerun under mpirun did not resume all 6 measurements:\n${again}")
  endif()
  set(extra_fields "|computed|resumed")  # run_info.json says what this run did
  expect_same_tree("${WORK_DIR}/plain/out" "${WORK_DIR}/np2/out")
elseif(MODE STREQUAL "bad_input")
  # Every rank reads the input, fails alike and exits 3; none is left waiting. And a failure of
  # rank 0 alone (its output path) ends the whole job with its exit code.
  foreach(case "--model;${WORK_DIR}/missing.json;--trials;100"
               "--model;${model};--trials;100;-o;${WORK_DIR}/no/such/dir/r.json")
    execute_process(COMMAND ${mpirun} -np 2 "${VCMM}" uncertainty --points
                            "${SOURCE_DIR}/examples/profiles/ring_171mm_scan.csv" --mode scanning
                            --temperature 20 ${case}
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
    if(NOT rc EQUAL 3)
      message(FATAL_ERROR "mpirun -np 2 vcmm uncertainty ${case}: exit ${rc}, expected 3\n${err}")
    endif()
    if(NOT err MATCHES "vcmm uncertainty: error: ")
      message(FATAL_ERROR "no error message for ${case}:\n${err}")
    endif()
  endforeach()
else()
  message(FATAL_ERROR "run_mpi_cli_test.cmake: unknown MODE '${MODE}'")
endif()
