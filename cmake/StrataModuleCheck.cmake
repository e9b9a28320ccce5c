# Script mode (cmake -P), run by the `strata_module_check` build step (cmake/StrataModules.cmake).
# STRATA_MODULE_RULES: "module=allowed1,allowed2,...|module2=..." for every module.
# Fails, listing every offending file:line, when a module's file includes a module outside its allowed list.
cmake_minimum_required(VERSION 3.25)
if(NOT DEFINED STRATA_SOURCE_DIR OR NOT DEFINED STRATA_MODULE_RULES)
  message(FATAL_ERROR "StrataModuleCheck.cmake: run by the build (cmake/StrataModules.cmake)")
endif()

string(REPLACE "|" ";" rules "${STRATA_MODULE_RULES}")
set(modules "")
foreach(rule IN LISTS rules)
  string(REGEX MATCH "^[^=]+" module "${rule}")
  list(APPEND modules ${module})
endforeach()

set(violations "")
foreach(rule IN LISTS rules)
  string(REGEX MATCH "^[^=]+" module "${rule}")
  string(REGEX REPLACE "^[^=]+=" "" allowed "${rule}")
  string(REPLACE "," ";" allowed "${allowed}")
  file(GLOB_RECURSE files
    ${STRATA_SOURCE_DIR}/include/strata/${module}/*.h
    ${STRATA_SOURCE_DIR}/src/${module}/*.h ${STRATA_SOURCE_DIR}/src/${module}/*.cpp)
  foreach(file IN LISTS files)
    file(STRINGS ${file} lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
    foreach(line IN LISTS lines)
      # "strata/<module>/x.h" (public) or "<module>/x.h" (internal, from src/).
      if(line MATCHES "#[ \t]*include[ \t]*\"(strata/)?([a-z_]+)/")
        set(target "${CMAKE_MATCH_2}")
        if(target IN_LIST modules AND NOT target IN_LIST allowed)
          file(RELATIVE_PATH rel ${STRATA_SOURCE_DIR} ${file})
          string(STRIP "${line}" line)
          list(APPEND violations "  ${rel}: ${line}  (module '${module}' does not depend on '${target}')")
        endif()
      endif()
    endforeach()
  endforeach()
endforeach()

if(violations)
  list(JOIN violations "\n" text)
  message(FATAL_ERROR
    "Module dependency check failed. A module may include only the modules it depends on "
    "(strata_add_module(... DEPENDS ...) in src/CMakeLists.txt and src/gl/CMakeLists.txt); "
    "adding the dependency instead is refused when it would make a cycle.\n${text}")
endif()
file(TOUCH ${STRATA_STAMP})
