# The module layering of docs/architecture.md, enforced by the compiler: a module's sources see
# only its own headers and those of the modules it links (and theirs, transitively), so an include
# of a module above it fails with "No such file or directory".
#
# src/ itself is never an include directory. Each module gets a folder of its own in the build
# tree, module-headers/<module>/, holding one symbolic link, <module> -> src/<module>; the module's
# target has that folder as a PUBLIC include directory, so it reaches every target that links the
# module, and no other. `#include "scene/scene.h"` keeps its spelling, and a header added to
# src/<module>/ is visible at once, with no edit here.
#
# tests/CMakeLists.txt runs cmake/check_layering.cmake as a test: it checks every module's headers
# against the table of docs/architecture.md and that a forbidden include really fails to compile.

set(RAYCAST_MODULE_HEADERS_DIR ${PROJECT_BINARY_DIR}/module-headers)

# Gives `target` the headers of `module` (a folder of src/) and records the include directories
# the target ends up with (its own and, transitively, those of what it links) in
# module-headers/<module>.include-dirs, for check_layering.cmake.
function(raycast_module_headers target module)
  set(folder ${RAYCAST_MODULE_HEADERS_DIR}/${module})
  file(MAKE_DIRECTORY ${folder})
  if(NOT IS_SYMLINK ${folder}/${module})
    file(CREATE_LINK ${PROJECT_SOURCE_DIR}/src/${module} ${folder}/${module} SYMBOLIC)
  endif()
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${folder}>)
  file(GENERATE OUTPUT ${RAYCAST_MODULE_HEADERS_DIR}/${module}.include-dirs
       CONTENT "$<TARGET_PROPERTY:${target},INCLUDE_DIRECTORIES>\n")
endfunction()
