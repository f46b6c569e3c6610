// Constant tables in flash on the AVR (PROGMEM + pgm_read, since avr-g++ has
// no __flash), plain const data elsewhere. Everything that reads a table
// declared MB2CO_FLASH goes through flash_read().
#pragma once
#include <stdint.h>
#include <string.h>

#ifdef __AVR__
#include <avr/pgmspace.h>
#define MB2CO_FLASH PROGMEM
namespace mb2co {
template <class T>
inline T flash_read(const T* p) {
  T v;
  memcpy_P(&v, p, sizeof(T));
  return v;
}
inline uint8_t flash_byte(const char* p) { return pgm_read_byte(p); }
}  // namespace mb2co
#else
#define MB2CO_FLASH
namespace mb2co {
template <class T>
inline T flash_read(const T* p) {
  return *p;
}
inline uint8_t flash_byte(const char* p) { return static_cast<uint8_t>(*p); }
}  // namespace mb2co
#endif
