# Warnings live in one INTERFACE target that every Strata target links privately.
add_library(strata_warnings INTERFACE)
add_library(strata::warnings ALIAS strata_warnings)
target_compile_options(strata_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion -Wnon-virtual-dtor
  -Wold-style-cast -Wcast-align -Woverloaded-virtual -Wnull-dereference -Wdouble-promotion
  # GCC 12 reports a false -Wrestrict inside libstdc++ for `"literal" + std::string&&`
  # (GCC bug 105329, fixed in GCC 13); it fires on ordinary string building.
  $<$<AND:$<CXX_COMPILER_ID:GNU>,$<VERSION_LESS:$<CXX_COMPILER_VERSION>,13>>:-Wno-restrict>
  $<$<BOOL:${STRATA_WERROR}>:-Werror>)
