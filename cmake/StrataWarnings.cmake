# Warnings live in one INTERFACE target that every Strata target links privately.
add_library(strata_warnings INTERFACE)
add_library(strata::warnings ALIAS strata_warnings)
target_compile_options(strata_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion -Wnon-virtual-dtor
  -Wold-style-cast -Wcast-align -Woverloaded-virtual -Wnull-dereference -Wdouble-promotion
  $<$<BOOL:${STRATA_WERROR}>:-Werror>)
