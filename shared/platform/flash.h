// Constant tables in flash on the AVR (PROGMEM + pgm_read, since avr-g++ has
// no __flash), plain const data elsewhere. Everything that reads a table
// declared MB2CO_FLASH goes through flash_read().
#pragma once
#include <stddef.h>
#include <stdint.h>
#include <string.h>

// For the few helpers on the OD's hot paths: the AVR build keeps small
// functions out of line for size (-fno-inline-small-functions), which would
// turn each field read into a call with its own register saves.
#define MB2CO_INLINE inline __attribute__((always_inline))

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
inline uint8_t flash_byte(const char* p) {
  return pgm_read_byte(p);
}
/// n bytes from flash into RAM, in place (flash_read() returns a copy).
inline void flash_copy(void* dst, const void* src, size_t n) {
  memcpy_P(dst, src, n);
}
// Single fields: one lpm per byte in place, no call and no copy (the OD reads
// one field of a row on every value access).
inline uint8_t flash_read(const uint8_t* p) {
  return pgm_read_byte(p);
}
inline uint16_t flash_read(const uint16_t* p) {
  return pgm_read_word(p);
}
inline uint32_t flash_read(const uint32_t* p) {
  return pgm_read_dword(p);
}
}  // namespace mb2co
#else
#define MB2CO_FLASH
namespace mb2co {
template <class T>
inline T flash_read(const T* p) {
  return *p;
}
inline uint8_t flash_byte(const char* p) {
  return static_cast<uint8_t>(*p);
}
inline void flash_copy(void* dst, const void* src, size_t n) {
  memcpy(dst, src, n);
}
}  // namespace mb2co
#endif
