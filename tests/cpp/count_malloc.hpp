// setbound tests — a counting malloc for the allocation tests (tests/cpp/test_alloc.cpp). Include
// it in exactly ONE translation unit of a test executable of its own (it replaces glibc's malloc
// family for the whole program; Eigen allocates with malloc or, for aligned storage, with the
// aligned variants). Under a sanitizer (which owns malloc) or without glibc nothing is replaced
// and SETBOUND_COUNT_MALLOC stays undefined: the tests then skip.
#pragma once

#include <atomic>
#include <cerrno>
#include <cstddef>

namespace {
std::atomic<long> g_allocations{0};
}

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_UNDEFINED__)
#define SETBOUND_COUNT_MALLOC 1
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void* malloc(std::size_t n) noexcept {
  ++g_allocations;
  return __libc_malloc(n);
}
void* calloc(std::size_t a, std::size_t b) noexcept {
  ++g_allocations;
  return __libc_calloc(a, b);
}
void* realloc(void* p, std::size_t n) noexcept {
  ++g_allocations;
  return __libc_realloc(p, n);
}
void* aligned_alloc(std::size_t al, std::size_t n) noexcept {
  ++g_allocations;
  return __libc_memalign(al, n);
}
void* memalign(std::size_t al, std::size_t n) noexcept {
  ++g_allocations;
  return __libc_memalign(al, n);
}
int posix_memalign(void** out, std::size_t al, std::size_t n) noexcept {
  ++g_allocations;
  void* p = __libc_memalign(al, n);
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}
}
#endif
