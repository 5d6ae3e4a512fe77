# Warnings for every target of ours (core folders, widgets, app, tests, bench, fuzz): -Wall -Wextra always,
# and -Werror when SHEARBENCH_WERROR=ON (CI's .ci/build and .ci/sanitize pass it), so a warning fails CI
# while a local build with a newer compiler still builds.
option(SHEARBENCH_WERROR "Treat compiler warnings as errors in our targets" OFF)

function(shearbench_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra
    # GCC 12's -Wrestrict reports false positives inside libstdc++'s std::string (GCC bug 105329).
    $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>)
  if(SHEARBENCH_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
