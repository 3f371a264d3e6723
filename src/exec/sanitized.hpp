// FACET_SANITIZED: 1 in builds under AddressSanitizer, ThreadSanitizer or MemorySanitizer (GCC's
// __SANITIZE_* macros, clang's __has_feature), else 0. sanitizer_build() (facet/sandbox.hpp) reports
// it at run time; code that a sanitizer build leaves out tests it at compile time.
#pragma once

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define FACET_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define FACET_SANITIZED 1
#endif
#endif
#ifndef FACET_SANITIZED
#define FACET_SANITIZED 0
#endif
