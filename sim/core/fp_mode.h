#pragma once
// Floating-point mode guard. Embree may leave the threads it runs on flushing
// denormals to zero (MXCSR FTZ/DAZ); a result that passes through the
// denormal range (a p-value near 1e-310, the Student tail of an extreme cell)
// would then depend on which thread computed it. IeeeDenormals restores
// IEEE gradual underflow for its scope, then the caller's mode.
#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#endif

namespace mcref {

class IeeeDenormals {
 public:
#if defined(__SSE__) || defined(__x86_64__)
  static constexpr unsigned kFlushBits = 0x8040u;  // FTZ (bit 15) | DAZ (bit 6)
  IeeeDenormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ & ~kFlushBits); }
  ~IeeeDenormals() { _mm_setcsr(saved_); }

 private:
  unsigned saved_;
#endif
 public:
  IeeeDenormals(const IeeeDenormals&) = delete;
  IeeeDenormals& operator=(const IeeeDenormals&) = delete;
};

}  // namespace mcref
