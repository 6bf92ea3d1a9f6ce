# mlod_set_warnings(target): the project's warning set; -Werror when MLOD_WERROR is on.
function(mlod_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
    -Wcast-align -Woverloaded-virtual -Wnull-dereference -Wimplicit-fallthrough)
  if(MLOD_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
