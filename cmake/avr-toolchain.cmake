# CMake toolchain for the Arduino Uno: ATmega328P at 16 MHz with Debian's
# gcc-avr 5.4 (C++14 is the ceiling, no libstdc++). Used only by the separate
# AVR project firmware/avr (see firmware/avr/build-and-check.sh):
#   cmake -S firmware/avr -B build/avr -G Ninja \
#         -DCMAKE_TOOLCHAIN_FILE=$PWD/cmake/avr-toolchain.cmake
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR avr)

set(MB2CO_AVR_MCU atmega328p CACHE STRING "avr-gcc -mmcu value")
set(MB2CO_AVR_F_CPU 16000000L CACHE STRING "CPU clock in Hz (F_CPU)")

find_program(CMAKE_C_COMPILER avr-gcc REQUIRED)
find_program(CMAKE_CXX_COMPILER avr-g++ REQUIRED)
set(CMAKE_ASM_COMPILER ${CMAKE_C_COMPILER})
# gcc-ar/gcc-ranlib load the LTO plugin: plain avr-ar would archive LTO
# objects without a symbol index and the link would find nothing.
find_program(CMAKE_AR avr-gcc-ar REQUIRED)
find_program(CMAKE_RANLIB avr-gcc-ranlib REQUIRED)
find_program(MB2CO_AVR_OBJCOPY avr-objcopy REQUIRED)
find_program(MB2CO_AVR_SIZE avr-size REQUIRED)
find_program(MB2CO_AVRDUDE avrdude)  # only the upload-* targets need it

# Compiler checks link a test program; a static library needs no startup
# files or linker script, and nothing host-side is ever run.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(_mb2co_avr_common "-mmcu=${MB2CO_AVR_MCU} -DF_CPU=${MB2CO_AVR_F_CPU}")
set(CMAKE_C_FLAGS_INIT "${_mb2co_avr_common} -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT "${_mb2co_avr_common} -ffunction-sections -fdata-sections -fno-exceptions -fno-rtti -fno-threadsafe-statics")
set(CMAKE_ASM_FLAGS_INIT "${_mb2co_avr_common} -x assembler-with-cpp")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-mmcu=${MB2CO_AVR_MCU} -Wl,--gc-sections")

# Size is what matters on a 32 KB / 2 KB part; -g costs no flash.
set(CMAKE_C_FLAGS_MINSIZEREL_INIT "-Os -g")
set(CMAKE_CXX_FLAGS_MINSIZEREL_INIT "-Os -g")

# Look for headers and libraries only in the AVR sysroot, programs on the host.
set(CMAKE_FIND_ROOT_PATH /usr/lib/avr)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
