# Cross build of the firmware core for an ARM Cortex-M4F (hard-float, FPv4-SP).
# Usage: cmake -B build-m4f -DCMAKE_TOOLCHAIN_FILE=cmake/arm-none-eabi-cortex-m4f.cmake
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
set(FCC_CPU_FLAGS "-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16")
set(CMAKE_C_FLAGS_INIT "${FCC_CPU_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${FCC_CPU_FLAGS} --specs=nano.specs --specs=nosys.specs -Wl,--gc-sections")
# The M4F's FPU is single precision: float is the natural real type there.
set(FCC_REAL "float" CACHE STRING "Real type of the firmware: double or float")
set(CMAKE_BUILD_TYPE MinSizeRel CACHE STRING "")
set(FCC_LINK_LIBM ON)
