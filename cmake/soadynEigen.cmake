# Where PyPI's cmeel-eigen puts Eigen: <site-packages>/cmeel.prefix, which
# holds share/eigen3/cmake/Eigen3Config.cmake. Used by soadyn's own build and
# by the installed soadynConfig.cmake, so a project that links soadyn finds
# Eigen without being told where it is.

# soadyn_cmeel_prefixes(<out> <python>): the cmeel.prefix folders on the
# sys.path of the Python interpreter <python> (empty when there are none, or
# when <python> cannot run).
function(soadyn_cmeel_prefixes out python)
  execute_process(
    COMMAND "${python}" -c
      "import sys, os; print(';'.join(os.path.join(p, 'cmeel.prefix') for p in sys.path if os.path.isdir(os.path.join(p, 'cmeel.prefix'))))"
    OUTPUT_VARIABLE prefixes OUTPUT_STRIP_TRAILING_WHITESPACE
    RESULT_VARIABLE status ERROR_QUIET)
  if(NOT status EQUAL 0)
    set(prefixes "")
  endif()
  set(${out} "${prefixes}" PARENT_SCOPE)
endfunction()
