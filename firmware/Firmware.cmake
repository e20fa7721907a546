# Included by the top-level CMakeLists.txt: builds the trigger-controller
# firmware (a separate project with its own compiler) through
# ExternalProject. Sets SPINEWATCH_FIRMWARE_ELF and the target
# trigger_firmware when it can; SPINEWATCH_FIRMWARE_MISSING says why not.
#
# First, whatever the AVR toolchain: trigger_protocol_host, the firmware's
# protocol parser and timing arithmetic built for the host from the same C
# files (the unit tests and the fuzz harness link it).
enable_language(C)
set(SPINEWATCH_FIRMWARE_COMMON ${CMAKE_CURRENT_LIST_DIR}/common)
add_library(trigger_protocol_host STATIC
  ${SPINEWATCH_FIRMWARE_COMMON}/trig_protocol.c ${SPINEWATCH_FIRMWARE_COMMON}/trig_timing.c
  ${SPINEWATCH_FIRMWARE_COMMON}/trig_eeprom_image.c ${SPINEWATCH_FIRMWARE_COMMON}/trig_crc16.c
  ${SPINEWATCH_FIRMWARE_COMMON}/trig_crc16_block.c)
target_include_directories(trigger_protocol_host PUBLIC ${SPINEWATCH_FIRMWARE_COMMON})
set_target_properties(trigger_protocol_host PROPERTIES C_STANDARD 99 C_STANDARD_REQUIRED ON C_EXTENSIONS OFF)
target_link_libraries(trigger_protocol_host PRIVATE spinewatch_warnings)

set(SPINEWATCH_FIRMWARE_MISSING "")
if(NOT SPINEWATCH_FIRMWARE)
  set(SPINEWATCH_FIRMWARE_MISSING "SPINEWATCH_FIRMWARE is OFF")
  return()
endif()

find_program(SPINEWATCH_AVR_GCC avr-gcc)
find_program(SPINEWATCH_AVR_OBJCOPY avr-objcopy)
find_program(SPINEWATCH_AVR_SIZE avr-size)
if(NOT SPINEWATCH_AVR_GCC OR NOT SPINEWATCH_AVR_OBJCOPY OR NOT SPINEWATCH_AVR_SIZE)
  set(SPINEWATCH_FIRMWARE_MISSING "avr-gcc/binutils-avr not found (scripts/install-deps installs gcc-avr, binutils-avr, avr-libc)")
  message(STATUS "firmware: ${SPINEWATCH_FIRMWARE_MISSING}; the simavr tests will report SKIPPED")
  return()
endif()

include(ExternalProject)
set(SPINEWATCH_FIRMWARE_DIR ${CMAKE_BINARY_DIR}/firmware)
set(SPINEWATCH_FIRMWARE_ELF ${SPINEWATCH_FIRMWARE_DIR}/trigger.elf)
ExternalProject_Add(trigger_firmware
  SOURCE_DIR ${CMAKE_CURRENT_LIST_DIR}
  BINARY_DIR ${SPINEWATCH_FIRMWARE_DIR}
  CMAKE_ARGS -DCMAKE_TOOLCHAIN_FILE=${CMAKE_CURRENT_LIST_DIR}/cmake/avr-gcc.cmake -DCMAKE_BUILD_TYPE=MinSizeRel
  INSTALL_COMMAND ""
  BUILD_ALWAYS ON
  BUILD_BYPRODUCTS ${SPINEWATCH_FIRMWARE_ELF} ${SPINEWATCH_FIRMWARE_DIR}/trigger.hex ${SPINEWATCH_FIRMWARE_DIR}/trigger.size.txt)
message(STATUS "firmware: ${SPINEWATCH_AVR_GCC} -> ${SPINEWATCH_FIRMWARE_ELF}")
