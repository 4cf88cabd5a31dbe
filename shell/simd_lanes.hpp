#pragma once
// Eight double lanes for the batched Type IV force kernel (shell/type4_batch_impl.hpp), written with the
// compiler's generic vector extension (GCC and Clang) at the target's native width: 2 x 4 doubles with
// AVX2, 4 x 2 with SSE2 or NEON, no intrinsics. (GCC lowers arithmetic on wider generic vectors well but
// scalarises their comparisons, which the selects below depend on.) Everything here has internal linkage
// and is force-inlined: this header is compiled once per instruction set (type4_batch_*.cpp), and a shared
// inline symbol would let the linker hand AVX2 code to a machine without it.
//
// Include only inside an anonymous namespace of a kernel translation unit.

constexpr int kLanes = 8;
#if defined(__AVX__)
constexpr int kNative = 4;
#else
constexpr int kNative = 2;
#endif
constexpr int kParts = kLanes / kNative;
typedef double Native __attribute__((vector_size(kNative * sizeof(double))));
typedef long long NativeInt __attribute__((vector_size(kNative * sizeof(long long))));

#define SF_INLINE static inline __attribute__((always_inline))
#define SF_PARTS for (int k_ = 0; k_ < kParts; ++k_)

struct Lanes {
  Native p[kParts];
  double operator[](int i) const { return p[i / kNative][i % kNative]; }
  void set(int i, double v) { p[i / kNative][i % kNative] = v; }
};
// Per lane: -1 (true) or 0 (false) from comparisons, or any 64-bit integer (the bit tricks of ln and e^x).
struct LaneMask {
  NativeInt p[kParts];
  long long operator[](int i) const { return p[i / kNative][i % kNative]; }
};

SF_INLINE Lanes splat(double a) {
  Lanes r;
  SF_PARTS r.p[k_] = Native{} + a;
  return r;
}
SF_INLINE LaneMask splat_int(long long a) {
  LaneMask r;
  SF_PARTS r.p[k_] = NativeInt{} + a;
  return r;
}
SF_INLINE Lanes as_lanes(const LaneMask& m) {
  Lanes r;
  SF_PARTS r.p[k_] = (Native)m.p[k_];
  return r;
}
SF_INLINE LaneMask as_mask(const Lanes& a) {
  LaneMask r;
  SF_PARTS r.p[k_] = (NativeInt)a.p[k_];
  return r;
}

#define SF_LANES_BINARY(OP)                                                       \
  SF_INLINE Lanes operator OP(const Lanes& a, const Lanes& b) {                   \
    Lanes r;                                                                      \
    SF_PARTS r.p[k_] = a.p[k_] OP b.p[k_];                                        \
    return r;                                                                     \
  }                                                                               \
  SF_INLINE Lanes operator OP(const Lanes& a, double b) { return a OP splat(b); } \
  SF_INLINE Lanes operator OP(double a, const Lanes& b) { return splat(a) OP b; }
SF_LANES_BINARY(+)
SF_LANES_BINARY(-)
SF_LANES_BINARY(*)
SF_LANES_BINARY(/)
#undef SF_LANES_BINARY
SF_INLINE Lanes operator-(const Lanes& a) {
  Lanes r;
  SF_PARTS r.p[k_] = -a.p[k_];
  return r;
}

#define SF_LANES_COMPARE(OP)                                               \
  SF_INLINE LaneMask operator OP(const Lanes& a, const Lanes& b) {         \
    LaneMask r;                                                            \
    SF_PARTS r.p[k_] = a.p[k_] OP b.p[k_];                                 \
    return r;                                                              \
  }                                                                        \
  SF_INLINE LaneMask operator OP(const Lanes& a, double b) { return a OP splat(b); }
SF_LANES_COMPARE(<)
SF_LANES_COMPARE(<=)
SF_LANES_COMPARE(>)
SF_LANES_COMPARE(>=)
#undef SF_LANES_COMPARE

#define SF_MASK_BINARY(OP)                                                 \
  SF_INLINE LaneMask operator OP(const LaneMask& a, const LaneMask& b) {   \
    LaneMask r;                                                            \
    SF_PARTS r.p[k_] = a.p[k_] OP b.p[k_];                                 \
    return r;                                                              \
  }                                                                        \
  SF_INLINE LaneMask operator OP(const LaneMask& a, long long b) { return a OP splat_int(b); }
SF_MASK_BINARY(&)
SF_MASK_BINARY(|)
SF_MASK_BINARY(+)
SF_MASK_BINARY(-)
#undef SF_MASK_BINARY
SF_INLINE LaneMask operator~(const LaneMask& a) {
  LaneMask r;
  SF_PARTS r.p[k_] = ~a.p[k_];
  return r;
}
SF_INLINE LaneMask operator<<(const LaneMask& a, int s) {
  LaneMask r;
  SF_PARTS r.p[k_] = a.p[k_] << s;
  return r;
}
SF_INLINE LaneMask operator>>(const LaneMask& a, int s) {
  LaneMask r;
  SF_PARTS r.p[k_] = a.p[k_] >> s;
  return r;
}

// Lanes {f(0), ..., f(7)}, built in registers (element-wise stores into a vector on the stack and then
// reading it whole would stall on store forwarding).
template <class F>
SF_INLINE Lanes gather(F f) {
  Lanes r;
#if defined(__AVX__)
  r.p[0] = Native{f(0), f(1), f(2), f(3)};
  r.p[1] = Native{f(4), f(5), f(6), f(7)};
#else
  r.p[0] = Native{f(0), f(1)};
  r.p[1] = Native{f(2), f(3)};
  r.p[2] = Native{f(4), f(5)};
  r.p[3] = Native{f(6), f(7)};
#endif
  return r;
}
static_assert(kLanes == 8, "gather lists eight lanes");

// m ? a : b per lane.
SF_INLINE Lanes select(const LaneMask& m, const Lanes& a, const Lanes& b) {
  return as_lanes((m & as_mask(a)) | (~m & as_mask(b)));
}
SF_INLINE bool any(const LaneMask& m) {
  NativeInt r = m.p[0];
  for (int k = 1; k < kParts; ++k) r |= m.p[k];
  long long o = 0;
  for (int i = 0; i < kNative; ++i) o |= r[i];
  return o != 0;
}
SF_INLINE bool all(const LaneMask& m) { return !any(~m); }

// With -fno-math-errno these per-lane loops become vector square roots.
SF_INLINE Lanes vsqrt(const Lanes& a) {
  Lanes r;
  SF_PARTS for (int i = 0; i < kNative; ++i) r.p[k_][i] = __builtin_sqrt(a.p[k_][i]);
  return r;
}
SF_INLINE Lanes vmax(const Lanes& a, const Lanes& b) { return select(a > b, a, b); }
SF_INLINE Lanes vmin(const Lanes& a, const Lanes& b) { return select(a < b, a, b); }
SF_INLINE Lanes vabs(const Lanes& a) { return as_lanes(as_mask(a) & 0x7fffffffffffffffLL); }

// 1.5 * 2^52: adding it rounds a double of magnitude < 2^51 to an integer held in the low mantissa bits.
constexpr double kRoundShift = 6755399441055744.0;
constexpr long long kRoundShiftBits = 0x4338000000000000LL;
// ln 2 split so that n * kLn2Hi is exact for |n| < 2^11 (the fdlibm split).
constexpr double kLn2Hi = 6.93147180369123816490e-01;
constexpr double kLn2Lo = 1.90821492927058770002e-10;

// e^x for |x| < 700 to about 1 ulp: x = n ln2 + r with |r| <= ln2/2, e^r by its Taylor series to r^13
// (remainder below 2e-17 relative), 2^n put into the exponent bits.
SF_INLINE Lanes vexp(Lanes x) {
  x = vmin(vmax(x, splat(-700.0)), splat(700.0));
  const Lanes shifted = x * 1.4426950408889634 + kRoundShift;  // x / ln2 rounded to an integer
  const Lanes n = shifted - kRoundShift;
  const LaneMask ni = as_mask(shifted) - kRoundShiftBits;
  const Lanes r = (x - n * kLn2Hi) - n * kLn2Lo;
  Lanes p = splat(1.0 / 6227020800.0);  // 1/13!
  p = p * r + 1.0 / 479001600.0;
  p = p * r + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * r + 1.0;
  p = p * r + 1.0;
  return p * as_lanes((ni + 1023) << 52);
}

// ln x for positive normal x to a few ulp: x = 2^e m with m in [sqrt(1/2), sqrt(2)),
// ln m = 2 atanh(f) with f = (m - 1)/(m + 1), |f| <= 0.172, by its odd series to f^23 (remainder below
// 1e-18 relative). Zero, negative, subnormal and non-finite inputs give garbage (callers mask them).
SF_INLINE Lanes vlog(Lanes x) {
  const LaneMask bits = as_mask(x);
  LaneMask e = ((bits >> 52) & 0x7ff) - 1023;
  Lanes m = as_lanes((bits & 0x000fffffffffffffLL) | 0x3ff0000000000000LL);  // in [1, 2)
  const LaneMask big = m > 1.4142135623730951;
  m = select(big, m * 0.5, m);
  e = e - big;  // big is -1 where true
  const Lanes f = (m - 1.0) / (m + 1.0);
  const Lanes s = f * f;
  Lanes p = splat(2.0 / 23.0);
  p = p * s + 2.0 / 21.0;
  p = p * s + 2.0 / 19.0;
  p = p * s + 2.0 / 17.0;
  p = p * s + 2.0 / 15.0;
  p = p * s + 2.0 / 13.0;
  p = p * s + 2.0 / 11.0;
  p = p * s + 2.0 / 9.0;
  p = p * s + 2.0 / 7.0;
  p = p * s + 2.0 / 5.0;
  p = p * s + 2.0 / 3.0;
  const Lanes ln_m = f * 2.0 + (f * s) * p;
  const Lanes ed = as_lanes(e + kRoundShiftBits) - kRoundShift;  // int64 -> double, exact for small e
  return ed * kLn2Hi + (ed * kLn2Lo + ln_m);
}

// Three-vectors of lanes.
struct Lanes3 {
  Lanes x, y, z;
};
SF_INLINE Lanes3 operator+(const Lanes3& a, const Lanes3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
SF_INLINE Lanes3 operator-(const Lanes3& a, const Lanes3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
SF_INLINE Lanes3 operator*(const Lanes& s, const Lanes3& a) { return {s * a.x, s * a.y, s * a.z}; }
SF_INLINE Lanes3 operator*(double s, const Lanes3& a) { return {s * a.x, s * a.y, s * a.z}; }
SF_INLINE Lanes dot(const Lanes3& a, const Lanes3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
SF_INLINE Lanes3 cross(const Lanes3& a, const Lanes3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
SF_INLINE Lanes3 zero3() { return {splat(0.0), splat(0.0), splat(0.0)}; }
