# raycast_warnings: the warning flags every raycast target compiles with.
add_library(raycast_warnings INTERFACE)
target_compile_options(raycast_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                                  -Wno-sign-conversion)
if(RAYCAST_WERROR)
  target_compile_options(raycast_warnings INTERFACE -Werror)
endif()
