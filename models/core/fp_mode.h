#pragma once
// Floating-point mode guard. A thread can run with denormals flushed to zero
// (MXCSR FTZ/DAZ: the mode Embree asks for; a validation run gave the same
// check a p-value of 1.9e-318 in one run and 0 in another). A result that
// passes through the denormal range (a p-value near 1e-310, the Student tail
// of an extreme cell) then depends on which thread computed it.
// IeeeDenormals sets IEEE gradual underflow for its scope, then restores the
// caller's mode (a no-op off x86).
#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#define MCREF_HAS_MXCSR 1
#endif

namespace mcref {

class IeeeDenormals {
 public:
  static constexpr unsigned kFlushBits = 0x8040u;  // FTZ (bit 15) | DAZ (bit 6)
#ifdef MCREF_HAS_MXCSR
  IeeeDenormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ & ~kFlushBits); }
  ~IeeeDenormals() { _mm_setcsr(saved_); }
#else
  IeeeDenormals() {}
#endif
  IeeeDenormals(const IeeeDenormals&) = delete;
  IeeeDenormals& operator=(const IeeeDenormals&) = delete;

 private:
#ifdef MCREF_HAS_MXCSR
  unsigned saved_;
#endif
};

}  // namespace mcref
