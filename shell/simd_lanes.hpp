#pragma once
// Double lanes for the batched Type IV force kernel (shell/type4_batch_impl.hpp), written with the compiler's
// generic vector extension (GCC and Clang) at the target's native width, no intrinsics: eight lanes in one
// register with AVX-512 (a batch in one pass), otherwise four, one AVX2 register or two SSE2 or NEON ones (a
// batch of eight as two groups). Four, not eight, below AVX-512: with eight lanes on AVX2 the jet and the
// adjoint keep about 30 vector registers live, twice what the machine has, and a third of the instructions
// were spills. (GCC lowers arithmetic on wider-than-native generic vectors well but scalarises their
// comparisons, which the selects below depend on.) Everything here has internal linkage and is force-inlined:
// this header is compiled once per instruction set (type4_batch_*.cpp), and a shared inline symbol would let
// the linker hand AVX2 code to a machine without it.
//
// Include only inside an anonymous namespace of a kernel translation unit.
#if defined(__AVX512F__)
// With AVX-512 a batch of 8 is one register and one pass: each dependency chain of the kernel (square roots,
// divisions, the e^x and ln polynomials, the Newton loop), whose latency rather than the instruction count or
// the memory traffic bounds the kernel, then serves 8 points instead of 4 (docs/performance.md, 2026-12-02).
constexpr int kLanes = 8;
constexpr int kNative = 8;
#else
constexpr int kLanes = 4;  // the kernel runs a batch of 8 points as two groups (type4_batch_impl.hpp)
#if defined(__AVX__)
constexpr int kNative = 4;
#else
constexpr int kNative = 2;
#endif
#endif
typedef double Native __attribute__((vector_size(kNative * sizeof(double))));
typedef long long NativeInt __attribute__((vector_size(kNative * sizeof(long long))));

#define SF_INLINE static inline __attribute__((always_inline))

// The parts are named members, not an array: GCC keeps named vector members in registers, while an array
// member indexed in a loop tends to stay in memory (every operation a load and a store).
struct Lanes {
#if defined(__AVX__)
  Native a;
  double operator[](int i) const { return a[i]; }
  void set(int i, double v) { a[i] = v; }
#else
  Native a, b;
  double operator[](int i) const { return i < kNative ? a[i] : b[i - kNative]; }
  void set(int i, double v) {
    if (i < kNative)
      a[i] = v;
    else
      b[i - kNative] = v;
  }
#endif
};
// Per lane: -1 (true) or 0 (false) from comparisons, or any 64-bit integer (the bit tricks of ln and e^x).
struct LaneMask {
#if defined(__AVX__)
  NativeInt a;
  long long operator[](int i) const { return a[i]; }
#else
  NativeInt a, b;
  long long operator[](int i) const { return i < kNative ? a[i] : b[i - kNative]; }
#endif
};

// r.m = EXPR(m) for every part m.
#if defined(__AVX__)
#define SF_EACH(r, EXPR) \
  do {                   \
    (r).a = EXPR(a);     \
  } while (0)
#else
#define SF_EACH(r, EXPR) \
  do {                   \
    (r).a = EXPR(a);     \
    (r).b = EXPR(b);     \
  } while (0)
#endif

SF_INLINE Lanes splat(double v) {
  Lanes r;
#define SF_E(m) (Native{} + v)
  SF_EACH(r, SF_E);
#undef SF_E
  return r;
}
SF_INLINE LaneMask splat_int(long long v) {
  LaneMask r;
#define SF_E(m) (NativeInt{} + v)
  SF_EACH(r, SF_E);
#undef SF_E
  return r;
}
SF_INLINE Lanes as_lanes(const LaneMask& x) {
  Lanes r;
#define SF_E(m) ((Native)x.m)
  SF_EACH(r, SF_E);
#undef SF_E
  return r;
}
SF_INLINE LaneMask as_mask(const Lanes& x) {
  LaneMask r;
#define SF_E(m) ((NativeInt)x.m)
  SF_EACH(r, SF_E);
#undef SF_E
  return r;
}

#define SF_E(m) (x.m SF_OP y.m)
#define SF_BINARY(R, A, B)                                                     \
  SF_INLINE R operator SF_OP_TOKEN(const A& x, const B& y) {                   \
    R r;                                                                       \
    SF_EACH(r, SF_E);                                                          \
    return r;                                                                  \
  }
// (The operator token is passed through SF_OP / SF_OP_TOKEN, redefined for each operator.)
#define SF_OP +
#define SF_OP_TOKEN +
SF_BINARY(Lanes, Lanes, Lanes)
SF_BINARY(LaneMask, LaneMask, LaneMask)
#undef SF_OP
#undef SF_OP_TOKEN
#define SF_OP -
#define SF_OP_TOKEN -
SF_BINARY(Lanes, Lanes, Lanes)
SF_BINARY(LaneMask, LaneMask, LaneMask)
#undef SF_OP
#undef SF_OP_TOKEN
#define SF_OP *
#define SF_OP_TOKEN *
SF_BINARY(Lanes, Lanes, Lanes)
#undef SF_OP
#undef SF_OP_TOKEN
#define SF_OP /
#define SF_OP_TOKEN /
SF_BINARY(Lanes, Lanes, Lanes)
#undef SF_OP
#undef SF_OP_TOKEN
#define SF_OP &
#define SF_OP_TOKEN &
SF_BINARY(LaneMask, LaneMask, LaneMask)
#undef SF_OP
#undef SF_OP_TOKEN
#define SF_OP |
#define SF_OP_TOKEN |
SF_BINARY(LaneMask, LaneMask, LaneMask)
#undef SF_OP
#undef SF_OP_TOKEN
#define SF_OP <
#define SF_OP_TOKEN <
SF_BINARY(LaneMask, Lanes, Lanes)
#undef SF_OP
#undef SF_OP_TOKEN
#define SF_OP <=
#define SF_OP_TOKEN <=
SF_BINARY(LaneMask, Lanes, Lanes)
#undef SF_OP
#undef SF_OP_TOKEN
#define SF_OP >
#define SF_OP_TOKEN >
SF_BINARY(LaneMask, Lanes, Lanes)
#undef SF_OP
#undef SF_OP_TOKEN
#define SF_OP >=
#define SF_OP_TOKEN >=
SF_BINARY(LaneMask, Lanes, Lanes)
#undef SF_OP
#undef SF_OP_TOKEN
#undef SF_BINARY
#undef SF_E

// Mixed with scalars.
SF_INLINE Lanes operator+(const Lanes& x, double y) { return x + splat(y); }
SF_INLINE Lanes operator+(double x, const Lanes& y) { return splat(x) + y; }
SF_INLINE Lanes operator-(const Lanes& x, double y) { return x - splat(y); }
SF_INLINE Lanes operator-(double x, const Lanes& y) { return splat(x) - y; }
SF_INLINE Lanes operator*(const Lanes& x, double y) { return x * splat(y); }
SF_INLINE Lanes operator*(double x, const Lanes& y) { return splat(x) * y; }
SF_INLINE Lanes operator/(const Lanes& x, double y) { return x / splat(y); }
SF_INLINE Lanes operator/(double x, const Lanes& y) { return splat(x) / y; }
SF_INLINE LaneMask operator<(const Lanes& x, double y) { return x < splat(y); }
SF_INLINE LaneMask operator<=(const Lanes& x, double y) { return x <= splat(y); }
SF_INLINE LaneMask operator>(const Lanes& x, double y) { return x > splat(y); }
SF_INLINE LaneMask operator>=(const Lanes& x, double y) { return x >= splat(y); }
SF_INLINE LaneMask operator&(const LaneMask& x, long long y) { return x & splat_int(y); }
SF_INLINE LaneMask operator|(const LaneMask& x, long long y) { return x | splat_int(y); }
SF_INLINE LaneMask operator+(const LaneMask& x, long long y) { return x + splat_int(y); }
SF_INLINE LaneMask operator-(const LaneMask& x, long long y) { return x - splat_int(y); }

SF_INLINE Lanes operator-(const Lanes& x) {
  Lanes r;
#define SF_E(m) (-x.m)
  SF_EACH(r, SF_E);
#undef SF_E
  return r;
}
SF_INLINE LaneMask operator~(const LaneMask& x) {
  LaneMask r;
#define SF_E(m) (~x.m)
  SF_EACH(r, SF_E);
#undef SF_E
  return r;
}
SF_INLINE LaneMask operator<<(const LaneMask& x, int s) {
  LaneMask r;
#define SF_E(m) (x.m << s)
  SF_EACH(r, SF_E);
#undef SF_E
  return r;
}
SF_INLINE LaneMask operator>>(const LaneMask& x, int s) {
  LaneMask r;
#define SF_E(m) (x.m >> s)
  SF_EACH(r, SF_E);
#undef SF_E
  return r;
}

// Lanes {f(0), ..., f(7)}, built in registers (element-wise stores into a vector on the stack and then
// reading it whole would stall on store forwarding).
template <class F>
SF_INLINE Lanes gather(F f) {
  Lanes r;
#if defined(__AVX512F__)
  r.a = Native{f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7)};
#elif defined(__AVX__)
  r.a = Native{f(0), f(1), f(2), f(3)};
#else
  r.a = Native{f(0), f(1)};
  r.b = Native{f(2), f(3)};
#endif
  return r;
}
static_assert(kLanes == (kNative == 8 ? 8 : 4), "gather lists the lanes of one Lanes");

// m ? a : b per lane.
SF_INLINE Lanes select(const LaneMask& m, const Lanes& a, const Lanes& b) {
  return as_lanes((m & as_mask(a)) | (~m & as_mask(b)));
}
SF_INLINE bool any(const LaneMask& m) {
#if defined(__AVX__)
  const NativeInt r = m.a;
#else
  const NativeInt r = m.a | m.b;
#endif
  long long o = 0;
  for (int i = 0; i < kNative; ++i) o |= r[i];
  return o != 0;
}
SF_INLINE bool all(const LaneMask& m) { return !any(~m); }

// With -fno-math-errno these per-lane loops become vector square roots.
SF_INLINE Native native_sqrt(Native x) {
  for (int i = 0; i < kNative; ++i) x[i] = __builtin_sqrt(x[i]);
  return x;
}
SF_INLINE Lanes vsqrt(const Lanes& x) {
  Lanes r;
#define SF_E(m) native_sqrt(x.m)
  SF_EACH(r, SF_E);
#undef SF_E
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
