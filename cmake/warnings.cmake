# SPDX-License-Identifier: MIT
# deepcut::warnings: our targets' warning flags (third-party headers are included as SYSTEM).
add_library(deepcut_warnings INTERFACE)
add_library(deepcut::warnings ALIAS deepcut_warnings)
target_compile_options(deepcut_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wno-missing-field-initializers)
if(DEEPCUT_STRICT)
  target_compile_options(deepcut_warnings INTERFACE -Werror)
endif()
