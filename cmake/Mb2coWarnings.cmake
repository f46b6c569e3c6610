# Warnings are errors on our own code (not on Debian's headers).
# -Wundef: a profile switch (MB2CO_CONFIG_*) tested without its header is an
# error, not a silent 0.
function(mb2co_warnings target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wconversion -Wsign-conversion -Wshadow -Wundef -Werror)
endfunction()

# shared/ must stay C++14 with GNU extensions (Debian avr-g++ 5.4 is the
# ceiling), no exceptions, no RTTI: the host build enforces the same dialect.
function(mb2co_portable target)
  set_target_properties(${target} PROPERTIES CXX_STANDARD 14 CXX_EXTENSIONS ON)
  target_compile_options(${target} PRIVATE -fno-exceptions -fno-rtti)
  mb2co_warnings(${target})
endfunction()

# Adds every sub-folder that has its own CMakeLists.txt (areas are owned by
# different people; no shared list to edit).
macro(mb2co_add_subdirs)
  file(GLOB _mb2co_children RELATIVE ${CMAKE_CURRENT_SOURCE_DIR} ${CMAKE_CURRENT_SOURCE_DIR}/*)
  list(SORT _mb2co_children)
  foreach(_child ${_mb2co_children})
    if(IS_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/${_child} AND EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${_child}/CMakeLists.txt)
      add_subdirectory(${_child})
    endif()
  endforeach()
endmacro()
