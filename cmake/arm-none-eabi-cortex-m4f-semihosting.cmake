# The Cortex-M4F cross build of cmake/arm-none-eabi-cortex-m4f.cmake, linked against newlib's
# full C library with semihosting (librdimon) instead of nano + nosys: the unit-test images of
# tests/target/ print, read their test vectors from the host and exit with a status through it
# (scripts/test target-unit). The startup is the tests' own (-nostartfiles, tests/target/).
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi-cortex-m4f.cmake)
set(CMAKE_EXE_LINKER_FLAGS_INIT "${FCC_CPU_FLAGS} --specs=rdimon.specs -nostartfiles -Wl,--gc-sections")
set(FCC_TARGET_TESTS ON CACHE BOOL "Build the unit tests as Cortex-M4F images run under QEMU")
