# Runs the report generator's CSV dump, then the NumPy baseline's comparison (CTest
# python.numpy_baseline). Fails when either step fails.
set(_csv "${WORKDIR}/numpy_check_cases.csv")
execute_process(COMMAND "${REPORT}" --dump "${_csv}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "lieservo_speed_error_report --dump failed: ${rc}")
endif()
execute_process(COMMAND "${PYTHON}" "${SCRIPT}" --check "${_csv}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "numpy_baseline.py --check failed: ${rc}")
endif()
