# Whole-build sanitizers: ASan + UBSan, errors abort so ctest sees them.
# -O1 and line tables only, after the build type's flags so they win: a sanitizer's report
# needs file:line in its stacks, not variables, and -O2 -g took most of the sanitizer build's
# CI minutes (scripts/test.sh).
if(MLOD_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer
                      -O1 $<IF:$<CXX_COMPILER_ID:Clang>,-gline-tables-only,-g1>)
  add_link_options(-fsanitize=address,undefined)
endif()
