# Post-link step of mb2co_avr_image: <image>.hex, <image>.eep (only when the
# image has EEPROM data; a stale one is removed), and the size report.
# cmake -DELF=<image>.elf -DOBJCOPY=avr-objcopy -DSIZE=avr-size -DMCU=atmega328p [-DHEX=OFF] -P this
# HEX=OFF (an OVERSIZE image): no .hex/.eep; stale ones are removed.
get_filename_component(_dir ${ELF} DIRECTORY)
get_filename_component(_name ${ELF} NAME_WE)
set(_base ${_dir}/${_name})

if(DEFINED HEX AND NOT HEX)
  file(REMOVE ${_base}.hex ${_base}.eep)
  execute_process(COMMAND ${SIZE} --format=berkeley ${ELF})
  message(STATUS "${_name}: OVERSIZE image, measured only (no .hex)")
  return()
endif()

execute_process(COMMAND ${OBJCOPY} -O ihex -R .eeprom ${ELF} ${_base}.hex
                RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "${_name}: avr-objcopy (hex) failed")
endif()

execute_process(COMMAND ${SIZE} -A ${ELF} OUTPUT_VARIABLE _sections RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "${_name}: avr-size failed")
endif()
if(_sections MATCHES "\n\\.eeprom[ \t]+[1-9]")
  execute_process(COMMAND ${OBJCOPY} -O ihex -j .eeprom --set-section-flags=.eeprom=alloc,load
                          --no-change-warnings --change-section-lma .eeprom=0 ${ELF} ${_base}.eep
                  RESULT_VARIABLE _rc)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "${_name}: avr-objcopy (eep) failed")
  endif()
else()
  file(REMOVE ${_base}.eep)
endif()

execute_process(COMMAND ${SIZE} --format=berkeley ${ELF})
execute_process(COMMAND ${SIZE} -C --mcu=${MCU} ${ELF})
