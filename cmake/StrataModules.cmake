# One library target per module (STYLE.md, "The house"; Magnum declares each library with its own
# dependencies in the same way).
#
#   strata_add_module(<name> [DEPENDS <module>...] [SOURCES <file>...]
#                     [PUBLIC_LIBS <target>...] [PRIVATE_LIBS <target>...])
#
# makes the static library strata_<name> (alias strata::<name>) from src/<name>/*.cpp plus SOURCES. Its
# public headers are include/strata/<name>/; src/ is a private include root, so that internal headers shared
# between modules (src/core/json_reader.h) are included as "core/json_reader.h". DEPENDS lists the Strata
# modules it uses (linked PUBLIC: their headers appear in its own); PUBLIC_LIBS and PRIVATE_LIBS are
# third-party targets.
#
# The module graph cannot have a cycle:
#   - declaring: a module may depend only on modules declared before it (src/CMakeLists.txt lists them
#     bottom-up), so a cycle cannot even be written down;
#   - including: strata_check_module_includes() adds the `strata_module_check` step to the default build. It
#     scans every module's headers and sources for #include "strata/<module>/..." and "<module>/..." and fails
#     the build, naming the file and line, when a module includes a module that it does not depend on
#     (directly or through its dependencies). An include that would close a cycle is always one of those.
include_guard(GLOBAL)

set(STRATA_MODULE_CHECK_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/StrataModuleCheck.cmake)
set_property(GLOBAL PROPERTY STRATA_MODULES "")

function(strata_add_module name)
  cmake_parse_arguments(PARSE_ARGV 1 M "" "" "DEPENDS;SOURCES;PUBLIC_LIBS;PRIVATE_LIBS")
  if(M_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "strata_add_module(${name}): unknown arguments ${M_UNPARSED_ARGUMENTS}")
  endif()
  # Everything this module may include: itself, its dependencies and everything they may include.
  set(allowed ${name})
  foreach(dep IN LISTS M_DEPENDS)
    if(NOT TARGET strata_${dep})
      message(FATAL_ERROR
        "strata_add_module(${name}): depends on '${dep}', which is not declared before it. Modules are "
        "declared bottom-up (src/CMakeLists.txt); a module that needs one declared later would make a cycle.")
    endif()
    get_property(dep_allowed GLOBAL PROPERTY STRATA_MODULE_${dep}_ALLOWED)
    list(APPEND allowed ${dep_allowed})
  endforeach()
  list(REMOVE_DUPLICATES allowed)
  set_property(GLOBAL PROPERTY STRATA_MODULE_${name}_ALLOWED ${allowed})
  set_property(GLOBAL APPEND PROPERTY STRATA_MODULES ${name})

  file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${name}/*.cpp)
  add_library(strata_${name} STATIC ${sources} ${M_SOURCES})
  add_library(strata::${name} ALIAS strata_${name})
  target_include_directories(strata_${name}
    PUBLIC ${PROJECT_SOURCE_DIR}/include
    PRIVATE ${PROJECT_SOURCE_DIR}/src)
  set(deps "")
  foreach(dep IN LISTS M_DEPENDS)
    list(APPEND deps strata::${dep})
  endforeach()
  target_link_libraries(strata_${name}
    PUBLIC ${deps} ${M_PUBLIC_LIBS}
    PRIVATE strata::warnings ${M_PRIVATE_LIBS})
endfunction()

# The `strata_module_check` build step (see the top of this file). Call once, after every module.
function(strata_check_module_includes)
  get_property(modules GLOBAL PROPERTY STRATA_MODULES)
  set(rules "")
  set(inputs "")
  foreach(module IN LISTS modules)
    get_property(allowed GLOBAL PROPERTY STRATA_MODULE_${module}_ALLOWED)
    string(REPLACE ";" "," allowed "${allowed}")
    list(APPEND rules "${module}=${allowed}")
    file(GLOB_RECURSE files CONFIGURE_DEPENDS
      ${PROJECT_SOURCE_DIR}/include/strata/${module}/*.h
      ${PROJECT_SOURCE_DIR}/src/${module}/*.h ${PROJECT_SOURCE_DIR}/src/${module}/*.cpp)
    list(APPEND inputs ${files})
  endforeach()
  string(REPLACE ";" "|" rules_arg "${rules}")
  set(stamp ${CMAKE_BINARY_DIR}/strata_module_check.stamp)
  add_custom_command(
    OUTPUT ${stamp}
    COMMAND ${CMAKE_COMMAND} "-DSTRATA_SOURCE_DIR=${PROJECT_SOURCE_DIR}" "-DSTRATA_MODULE_RULES=${rules_arg}"
            "-DSTRATA_STAMP=${stamp}" -P ${STRATA_MODULE_CHECK_SCRIPT}
    DEPENDS ${inputs} ${STRATA_MODULE_CHECK_SCRIPT}
    COMMENT "Checking that each module includes only the modules it depends on"
    VERBATIM)
  add_custom_target(strata_module_check ALL DEPENDS ${stamp})
  # Every module's build waits for the check, so a forbidden include stops the build before it compiles.
  foreach(module IN LISTS modules)
    add_dependencies(strata_${module} strata_module_check)
  endforeach()
endfunction()
