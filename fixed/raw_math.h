// Square roots and trigonometry on raw Q32.32 values, as templates over the
// 128-bit backend U. Defined in fixed/sqrt.cpp and fixed/trig.cpp and
// instantiated there for both backends, so tests can run each function through
// NativeU128 and PortableU128 and compare the bits.
#pragma once

#include <cstdint>

#include "fixed/u128.h"

namespace bitstep::raw {

// floor(sqrt(n)) for any 128-bit n.
template <class U>
uint64_t isqrt_floor(U n);

template <class U>
int64_t sqrt(int64_t a);
template <class U>
int64_t rsqrt(int64_t a);
// sqrt(v0^2 + ... ) correctly rounded, for 3 components.
template <class U>
int64_t length3(int64_t x, int64_t y, int64_t z);
// v / |v| for n = 3 or 4 components, each within 1 ulp; false (and zeros) for
// the zero vector.
template <class U>
bool normalize(const int64_t* in, int64_t* out, int n);

template <class U>
int64_t sin(int64_t a);
template <class U>
int64_t cos(int64_t a);
template <class U>
int64_t tan(int64_t a);
template <class U>
int64_t atan2(int64_t y, int64_t x);
template <class U>
int64_t asin(int64_t a);
template <class U>
int64_t acos(int64_t a);

}  // namespace bitstep::raw
