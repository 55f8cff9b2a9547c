# A test (cmake -P, run by CTest; see tests/CMakeLists.txt) that the build enforces the module
# layering of docs/architecture.md (cmake/raycast_layering.cmake). With the include directories
# each module's target really compiles with (BUILD/module-headers/<module>.include-dirs), it checks:
#  1. every header of each module preprocesses: its includes stay within what the module sees
#     (the build compiles the .cpp files, but a header that no .cpp of its module includes would
#     otherwise go unchecked);
#  2. each module sees exactly the modules the table below allows, itself and those below it,
#     and no others (probed with __has_include, one compiler run per module);
#  3. a forbidden include really fails to compile: bvh including a geometry header.
# The table is written here from the document, not read from the build, so that a new link
# between modules fails this test until the document and the table say so too.
#
#   cmake -DCOMPILER=c++ -DSOURCE_DIR=... -DHEADERS_DIR=BUILD/module-headers -DWORK_DIR=... -P check_layering.cmake

# docs/architecture.md, "depends on": the modules each one uses directly.
set(uses_base "")
set(uses_math base)
set(uses_geometry math)
set(uses_bvh math)
set(uses_scene geometry bvh)
set(uses_sceneio scene)
set(uses_image math)
set(uses_render scene image)
set(uses_view render sceneio image)
set(uses_cli view render sceneio image)

foreach(variable COMPILER SOURCE_DIR HEADERS_DIR WORK_DIR)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "check_layering.cmake needs -D${variable}=...")
  endif()
endforeach()
file(MAKE_DIRECTORY ${WORK_DIR})

# The modules a module may see: itself and everything it uses, transitively.
function(visible_modules module out)
  set(result ${module})
  foreach(used IN LISTS uses_${module})
    visible_modules(${used} below)
    list(APPEND result ${below})
  endforeach()
  list(REMOVE_DUPLICATES result)
  set(${out} ${result} PARENT_SCOPE)
endfunction()

# Runs the compiler on `source` with the module's include directories; sets <prefix>_status and
# <prefix>_output (stdout and stderr together).
function(run_compiler module prefix)
  file(READ ${HEADERS_DIR}/${module}.include-dirs dirs)
  string(STRIP "${dirs}" dirs)
  set(include_flags "")
  foreach(dir IN LISTS dirs)
    list(APPEND include_flags "-I${dir}")
  endforeach()
  execute_process(COMMAND ${COMPILER} -std=c++17 ${include_flags} ${ARGN}
                  RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE output)
  set(${prefix}_status ${status} PARENT_SCOPE)
  set(${prefix}_output "${output}" PARENT_SCOPE)
endfunction()

file(GLOB entries RELATIVE ${SOURCE_DIR}/src ${SOURCE_DIR}/src/*)
set(modules "")
foreach(entry IN LISTS entries)
  if(IS_DIRECTORY ${SOURCE_DIR}/src/${entry})
    list(APPEND modules ${entry})
  endif()
endforeach()
list(SORT modules)

# One header of each module, to probe for.
foreach(module IN LISTS modules)
  if(NOT DEFINED uses_${module})
    message(FATAL_ERROR "src/${module}/ is a module that docs/architecture.md's table (and the copy of it in "
                        "cmake/check_layering.cmake) does not list: add it to both")
  endif()
  if(NOT EXISTS ${HEADERS_DIR}/${module}.include-dirs)
    message(FATAL_ERROR "src/${module}/ has no header tree in ${HEADERS_DIR}: give its target "
                        "raycast_module_headers() (src/CMakeLists.txt)")
  endif()
  file(GLOB headers RELATIVE ${SOURCE_DIR}/src/${module} ${SOURCE_DIR}/src/${module}/*.h)
  list(SORT headers)
  list(GET headers 0 probe_${module})
endforeach()

set(failures "")  # a text, not a list: compiler output may hold semicolons
foreach(module IN LISTS modules)
  # 1. Its headers include only what it sees.
  file(GLOB headers RELATIVE ${SOURCE_DIR}/src ${SOURCE_DIR}/src/${module}/*.h ${SOURCE_DIR}/src/${module}/*.inl)
  set(text "")
  foreach(header IN LISTS headers)
    string(APPEND text "#include \"${header}\"\n")
  endforeach()
  file(WRITE ${WORK_DIR}/${module}_headers.cpp "${text}")
  run_compiler(${module} headers -E ${WORK_DIR}/${module}_headers.cpp -o ${WORK_DIR}/${module}_headers.i)
  if(NOT headers_status EQUAL 0)
    string(APPEND failures "a header of src/${module}/ includes a module that ${module} may not see:\n${headers_output}\n")
  endif()

  # 2. It sees exactly the modules the table allows.
  set(text "")
  foreach(other IN LISTS modules)
    string(APPEND text "#if __has_include(\"${other}/${probe_${other}}\")\nlayering_sees ${other}\n#endif\n")
  endforeach()
  file(WRITE ${WORK_DIR}/${module}_sees.cpp "${text}")
  run_compiler(${module} sees -E -P ${WORK_DIR}/${module}_sees.cpp -o ${WORK_DIR}/${module}_sees.i)
  if(NOT sees_status EQUAL 0)
    string(APPEND failures "the visibility probe of ${module} did not preprocess:\n${sees_output}\n")
    continue()
  endif()
  file(STRINGS ${WORK_DIR}/${module}_sees.i seen_lines REGEX "^layering_sees ")
  set(seen "")
  foreach(line IN LISTS seen_lines)
    string(REPLACE "layering_sees " "" name "${line}")
    list(APPEND seen ${name})
  endforeach()
  visible_modules(${module} allowed)
  list(SORT seen)
  list(SORT allowed)
  if(NOT seen STREQUAL allowed)
    string(APPEND failures "${module} sees the headers of '${seen}' but the table allows '${allowed}'\n")
  endif()
  message(STATUS "${module} sees: ${seen}")
endforeach()

# 3. A forbidden include fails to compile, and because of the include (not of something else).
set(forbidden "geometry/${probe_geometry}")
file(WRITE ${WORK_DIR}/forbidden.cpp "#include \"${forbidden}\"\nint main() { return 0; }\n")
run_compiler(bvh forbidden -fsyntax-only ${WORK_DIR}/forbidden.cpp)
if(forbidden_status EQUAL 0)
  string(APPEND failures "bvh compiled an include of ${forbidden}, which it must not see\n")
elseif(NOT forbidden_output MATCHES "${probe_geometry}")
  string(APPEND failures "an include of ${forbidden} in bvh failed for another reason:\n${forbidden_output}\n")
endif()

if(failures)
  message(FATAL_ERROR "module layering broken:\n${failures}")
endif()
message(STATUS "module layering: every module sees only the modules below it")
