# Whole-build sanitizers: ASan + UBSan, errors abort so ctest sees them.
if(MLOD_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g)
  add_link_options(-fsanitize=address,undefined)
endif()
