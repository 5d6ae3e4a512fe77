#pragma once
// SB_TEST_ASAN is defined when AddressSanitizer is on (clang: __has_feature; gcc: __SANITIZE_ADDRESS__). Tests
// that replace or measure the allocator skip themselves then: ASan owns malloc and operator new.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SB_TEST_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define SB_TEST_ASAN 1
#endif
