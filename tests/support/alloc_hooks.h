// Counts every allocation while g_counting is set: operator new here, malloc,
// calloc and realloc through the linker's --wrap (the executable links with
// -Wl,--wrap=malloc -Wl,--wrap=calloc -Wl,--wrap=realloc). For the tests that
// prove portable code allocates nothing at run time (tests/canopen_noheap,
// tests/serialnet/no_heap). Definitions: include in exactly one source file
// of the executable.
#pragma once
#include <atomic>
#include <cstdlib>
#include <new>

static std::atomic<bool> g_counting{false};
static std::atomic<int> g_calls{0};

extern "C" {
void* __real_malloc(size_t);
void* __real_calloc(size_t, size_t);
void* __real_realloc(void*, size_t);
void* __wrap_malloc(size_t n) {
  if (g_counting) ++g_calls;
  return __real_malloc(n);
}
void* __wrap_calloc(size_t n, size_t m) {
  if (g_counting) ++g_calls;
  return __real_calloc(n, m);
}
void* __wrap_realloc(void* p, size_t n) {
  if (g_counting) ++g_calls;
  return __real_realloc(p, n);
}
}

void* operator new(size_t n) {
  if (g_counting) ++g_calls;
  void* p = std::malloc(n);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, size_t) noexcept {
  std::free(p);
}
