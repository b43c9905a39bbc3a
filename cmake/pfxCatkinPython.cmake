# catkin runs its generators with PYTHON_EXECUTABLE. The first python3 on PATH may be a
# pyenv or virtualenv interpreter without catkin_pkg, which Debian installs for
# /usr/bin/python3 only: take the first interpreter that can import it.
if(NOT DEFINED PYTHON_EXECUTABLE)
  find_program(PFX_PATH_PYTHON3 python3)
  foreach(candidate ${PFX_PATH_PYTHON3} /usr/bin/python3)
    execute_process(COMMAND ${candidate} -c "import catkin_pkg" RESULT_VARIABLE failed
                    OUTPUT_QUIET ERROR_QUIET)
    if(NOT failed)
      set(PYTHON_EXECUTABLE ${candidate} CACHE FILEPATH "Python that catkin runs")
      break()
    endif()
  endforeach()
endif()
