# FCC_HOST_ARCH (host builds only; off by default): fcc and every host tool built with
# -march=${FCC_HOST_ARCH}, e.g. x86-64-v3 (AVX2, FMA, BMI2), for the machine they run on.
#
#  * No FMA: a*b+c fused into one instruction is rounded once instead of twice, and the
#    results would no longer be the portable build's bit for bit (tests/python/fcc/
#    test_host_arch.py compares the two builds' outputs).  -ffp-contract=off alone is not
#    enough: GCC 12's vectoriser still fuses the complex-multiply pattern of fcc_mat64_eig into
#    vfmsubadd231pd (seen in lqg_design: the last 1-3 digits of its gains moved), so -mno-fma
#    too.  The level's other instructions (AVX2 on 256-bit registers, BMI2, MOVBE) stay; they
#    do not change a result: without -ffast-math GCC does not reorder a floating-point sum.
#  * At configure time: this machine's /proc/cpuinfo (FCC_CPUINFO) must have the level's
#    flags (one line and a failed configure otherwise).
#  * At run time: every program checks the CPU before main (host_arch_check.c, compiled for the
#    portable x86-64): a copy run on an older CPU says so in one line and exits 1, instead of
#    dying of SIGILL somewhere later.
if(CMAKE_CROSSCOMPILING)
  message(FATAL_ERROR "FCC_HOST_ARCH is for host builds; the Cortex-M4F image has its own flags")
endif()

set(_fcc_arch_flags_x86-64-v2 cx16 lahf_lm popcnt pni sse4_1 sse4_2 ssse3)
set(_fcc_arch_flags_x86-64-v3 ${_fcc_arch_flags_x86-64-v2} avx avx2 bmi1 bmi2 f16c fma abm movbe xsave)
set(_fcc_arch_flags_x86-64-v4 ${_fcc_arch_flags_x86-64-v3} avx512f avx512bw avx512cd avx512dq avx512vl)
if(NOT DEFINED _fcc_arch_flags_${FCC_HOST_ARCH})
  message(FATAL_ERROR "FCC_HOST_ARCH must be x86-64-v2, x86-64-v3 or x86-64-v4, not '${FCC_HOST_ARCH}'")
endif()

set(FCC_CPUINFO "/proc/cpuinfo" CACHE FILEPATH "the CPU description FCC_HOST_ARCH is checked against")
file(STRINGS "${FCC_CPUINFO}" _fcc_cpu_flags REGEX "^flags" LIMIT_COUNT 1)
string(REGEX REPLACE "^flags[ \t]*:[ \t]*" "" _fcc_cpu_flags "${_fcc_cpu_flags}")
separate_arguments(_fcc_cpu_flags)
set(_fcc_missing "")
foreach(flag IN LISTS _fcc_arch_flags_${FCC_HOST_ARCH})
  if(NOT flag IN_LIST _fcc_cpu_flags)
    list(APPEND _fcc_missing ${flag})
  endif()
endforeach()
if(_fcc_missing)
  list(JOIN _fcc_missing " " _fcc_missing)
  message(FATAL_ERROR "FCC_HOST_ARCH=${FCC_HOST_ARCH}: this CPU (${FCC_CPUINFO}) lacks ${_fcc_missing}; "
                      "configure without -DFCC_HOST_ARCH for the portable build")
endif()

add_compile_options(-march=${FCC_HOST_ARCH} -ffp-contract=off -mno-fma)
add_library(fcc_host_arch_check OBJECT ${CMAKE_CURRENT_LIST_DIR}/host_arch_check.c)
target_compile_definitions(fcc_host_arch_check PRIVATE FCC_HOST_ARCH_NAME="${FCC_HOST_ARCH}")
# the check itself must run on any x86-64 (the later -march wins)
target_compile_options(fcc_host_arch_check PRIVATE -march=x86-64)
link_libraries(fcc_host_arch_check)
