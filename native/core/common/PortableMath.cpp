#include "common/PortableMath.h"

#include <cmath>  // only exact or IEEE-specified operations: sqrt, fabs, floor, fmod, frexp, ldexp
#include <limits>

namespace mwb::portable {
namespace {

// Multiples of pi as the nearest double plus the rest, so sums keep their last bits.
constexpr double kPi = 3.14159265358979311600e+00;
constexpr double kPiLow = 1.2246467991473532e-16;
constexpr double kPiOver2 = 1.57079632679489655800e+00;
constexpr double kPiOver2Low = 6.123233995736766e-17;
constexpr double kPiOver4 = 7.85398163397448278999e-01;
constexpr double kPiOver6 = 5.2359877559829893e-01;
constexpr double kPiOver6Low = -5.360408832255455e-17;
constexpr double kTwoPi = 6.28318530717958623200e+00;
constexpr double kTwoOverPi = 6.36619772367581382433e-01;
constexpr double kSqrt3 = 1.73205080756887719318e+00;
constexpr double kTanPiOver12 = 2.67949192431122695760e-01;
// pi/2 in three parts of 33 bits each (Cody and Waite), so k * part is exact for |k| < 2^20 and
// the reduction x - k pi/2 keeps about 100 bits of pi/2.
constexpr double kPiOver2Part1 = 1.57079632673412561417e+00;
constexpr double kPiOver2Part2 = 6.07710050630396597660e-11;
constexpr double kPiOver2Part3 = 2.02226624871116645580e-21;
// ln 2 in two parts; kLn2High has 32 bits, so k * kLn2High is exact for every exponent k.
constexpr double kLn2High = 6.93147180369123816490e-01;
constexpr double kLn2Low = 1.90821492927058770002e-10;
constexpr double kInvLn2 = 1.44269504088896338700e+00;
constexpr double kSqrtHalf = 7.07106781186547572737e-01;
constexpr double kReduceLimit = 5.0e5;  // |k| stays below 2^19 for the three-part reduction
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Taylor series on |r| <= pi/4; the first omitted terms are below 1e-19.
double sin_kernel(double r) {
    const double r2 = r * r;
    double p = 1.0 / 355687428096000.0;   // 1/17!
    p = p * r2 - 1.0 / 1307674368000.0;   // 1/15!
    p = p * r2 + 1.0 / 6227020800.0;      // 1/13!
    p = p * r2 - 1.0 / 39916800.0;        // 1/11!
    p = p * r2 + 1.0 / 362880.0;          // 1/9!
    p = p * r2 - 1.0 / 5040.0;            // 1/7!
    p = p * r2 + 1.0 / 120.0;             // 1/5!
    p = p * r2 - 1.0 / 6.0;               // 1/3!
    return r + r * r2 * p;
}

double cos_kernel(double r) {
    const double r2 = r * r;
    double p = -1.0 / 6402373705728000.0;  // 1/18!
    p = p * r2 + 1.0 / 20922789888000.0;   // 1/16!
    p = p * r2 - 1.0 / 87178291200.0;      // 1/14!
    p = p * r2 + 1.0 / 479001600.0;        // 1/12!
    p = p * r2 - 1.0 / 3628800.0;          // 1/10!
    p = p * r2 + 1.0 / 40320.0;            // 1/8!
    p = p * r2 - 1.0 / 720.0;              // 1/6!
    p = p * r2 + 1.0 / 24.0;               // 1/4!
    p = p * r2 - 0.5;
    return 1.0 + r2 * p;
}

/// x - k pi/2 with |result| about pi/4 at most; `quadrant` gets k mod 4. x must be finite.
double reduce_quarter_turns(double x, int* quadrant) {
    if (std::fabs(x) <= kPiOver4) {
        *quadrant = 0;
        return x;
    }
    // Far out (never reached by simulation angles), fold into one turn first: fmod is exact, so
    // the result is still the same everywhere, if less accurate.
    if (std::fabs(x) >= kReduceLimit) x = std::fmod(x, kTwoPi);
    const double k = std::floor(x * kTwoOverPi + 0.5);
    *quadrant = static_cast<int>(static_cast<long long>(k) & 3);
    return ((x - k * kPiOver2Part1) - k * kPiOver2Part2) - k * kPiOver2Part3;
}

// atan on |t| <= tan(pi/12) ~ 0.268: Taylor series to t^29 (omitted terms below 1e-19).
double atan_kernel(double t) {
    const double t2 = t * t;
    double p = 1.0 / 29.0;
    for (int odd = 27; odd >= 3; odd -= 2) p = p * t2 + ((odd / 2) % 2 ? -1.0 : 1.0) / odd;
    return t + t * t2 * p;
}

/// atan on [0, 1]: above tan(pi/12), atan(x) = pi/6 + atan((x sqrt3 - 1) / (x + sqrt3)).
double atan_unit(double x) {
    if (x > kTanPiOver12) return kPiOver6 + (kPiOver6Low + atan_kernel((x * kSqrt3 - 1.0) / (x + kSqrt3)));
    return atan_kernel(x);
}

bool is_odd_integer(double y) {
    return std::fabs(y) < 9007199254740992.0 && std::floor(y) == y && std::fmod(y, 2.0) != 0.0;
}

}  // namespace

void sincos(double x, double* sin_x, double* cos_x) {
    if (!std::isfinite(x)) {
        *sin_x = *cos_x = kNaN;
        return;
    }
    if (x == 0.0) {  // keeps the sign of zero
        *sin_x = x;
        *cos_x = 1.0;
        return;
    }
    int quadrant = 0;
    const double r = reduce_quarter_turns(x, &quadrant);
    const double s = sin_kernel(r), c = cos_kernel(r);
    switch (quadrant) {
        case 0: *sin_x = s; *cos_x = c; break;
        case 1: *sin_x = c; *cos_x = -s; break;
        case 2: *sin_x = -s; *cos_x = -c; break;
        default: *sin_x = -c; *cos_x = s; break;
    }
}

double sin(double x) {
    double s, c;
    sincos(x, &s, &c);
    return s;
}

double cos(double x) {
    double s, c;
    sincos(x, &s, &c);
    return c;
}

double atan2(double y, double x) {
    if (std::isnan(x) || std::isnan(y)) return x + y;
    if (y == 0.0) return std::signbit(x) ? std::copysign(kPi, y) : y;
    if (x == 0.0) return std::copysign(kPiOver2, y);
    if (std::isinf(x)) {
        if (std::isinf(y)) return std::copysign(x > 0 ? kPiOver4 : kPi - kPiOver4, y);
        return x > 0 ? std::copysign(0.0, y) : std::copysign(kPi, y);
    }
    if (std::isinf(y)) return std::copysign(kPiOver2, y);
    const double ax = std::fabs(x), ay = std::fabs(y);
    double angle = ay <= ax ? atan_unit(ay / ax) : kPiOver2 + (kPiOver2Low - atan_unit(ax / ay));
    if (x < 0) angle = kPi + (kPiLow - angle);
    return std::copysign(angle, y);
}

double asin(double x) {
    if (!(std::fabs(x) <= 1.0)) return kNaN;
    return atan2(x, std::sqrt((1.0 - x) * (1.0 + x)));
}

double acos(double x) {
    if (!(std::fabs(x) <= 1.0)) return kNaN;
    return atan2(std::sqrt((1.0 - x) * (1.0 + x)), x);
}

double exp(double x) {
    if (std::isnan(x)) return x;
    if (x > 709.782712893384) return kInf;
    if (x < -745.1332191019412) return 0.0;
    const double k = std::floor(x * kInvLn2 + 0.5);
    const double r = (x - k * kLn2High) - k * kLn2Low;  // |r| <= ln2 / 2
    // Taylor series to r^17 / 17!; the first omitted term is below 1e-24.
    double p = 1.0;
    for (int n = 17; n >= 1; --n) p = 1.0 + p * r / n;
    return std::ldexp(p, static_cast<int>(k));
}

double log(double x) {
    if (std::isnan(x)) return x;
    if (x < 0) return kNaN;
    if (x == 0) return -kInf;
    if (std::isinf(x)) return x;
    int e = 0;
    double m = std::frexp(x, &e);  // x = m 2^e, m in [1/2, 1)
    if (m < kSqrtHalf) {
        m *= 2;
        e -= 1;
    }
    // log m = 2 atanh s with s = (m - 1) / (m + 1), |s| <= 0.172: series to s^27.
    const double s = (m - 1.0) / (m + 1.0);
    const double s2 = s * s;
    double p = 1.0 / 27.0;
    for (int odd = 25; odd >= 3; odd -= 2) p = p * s2 + 1.0 / odd;
    const double log_m = 2.0 * s + 2.0 * s * s2 * p;
    return e * kLn2High + (e * kLn2Low + log_m);
}

double pow(double x, double y) {
    if (y == 0.0 || x == 1.0) return 1.0;
    if (std::isnan(x) || std::isnan(y)) return x + y;
    const bool odd = is_odd_integer(y);
    if (x == 0.0) {
        if (y > 0) return odd ? x : 0.0;
        return odd ? std::copysign(kInf, x) : kInf;
    }
    if (std::isinf(y)) {
        const double ax = std::fabs(x);
        if (ax == 1.0) return 1.0;
        return (ax > 1.0) == (y > 0) ? kInf : 0.0;
    }
    if (std::isinf(x)) {
        const double magnitude = y > 0 ? kInf : 0.0;
        return x < 0 && odd ? -magnitude : magnitude;
    }
    double sign = 1.0;
    if (x < 0) {
        if (std::floor(y) != y) return kNaN;
        if (odd) sign = -1.0;
        x = -x;
    }
    return sign * exp(y * log(x));
}

double hypot(double x, double y) {
    x = std::fabs(x);
    y = std::fabs(y);
    if (std::isinf(x) || std::isinf(y)) return kInf;
    if (std::isnan(x) || std::isnan(y)) return x + y;
    const double big = x > y ? x : y, small = x > y ? y : x;
    if (big == 0.0) return 0.0;
    const double ratio = small / big;
    return big * std::sqrt(1.0 + ratio * ratio);
}

}  // namespace mwb::portable

extern "C" {
double mwb_portable_sin(double x) { return mwb::portable::sin(x); }
double mwb_portable_cos(double x) { return mwb::portable::cos(x); }
void mwb_portable_sincos(double x, double* sin_x, double* cos_x) { mwb::portable::sincos(x, sin_x, cos_x); }
double mwb_portable_atan2(double y, double x) { return mwb::portable::atan2(y, x); }
double mwb_portable_asin(double x) { return mwb::portable::asin(x); }
double mwb_portable_acos(double x) { return mwb::portable::acos(x); }
float mwb_portable_sinf(float x) { return static_cast<float>(mwb::portable::sin(x)); }
float mwb_portable_cosf(float x) { return static_cast<float>(mwb::portable::cos(x)); }
void mwb_portable_sincosf(float x, float* sin_x, float* cos_x) {
    double s, c;
    mwb::portable::sincos(x, &s, &c);
    *sin_x = static_cast<float>(s);
    *cos_x = static_cast<float>(c);
}
float mwb_portable_atan2f(float y, float x) { return static_cast<float>(mwb::portable::atan2(y, x)); }
float mwb_portable_asinf(float x) { return static_cast<float>(mwb::portable::asin(x)); }
float mwb_portable_acosf(float x) { return static_cast<float>(mwb::portable::acos(x)); }
double mwb_portable_exp(double x) { return mwb::portable::exp(x); }
double mwb_portable_log(double x) { return mwb::portable::log(x); }
double mwb_portable_pow(double x, double y) { return mwb::portable::pow(x, y); }
}
