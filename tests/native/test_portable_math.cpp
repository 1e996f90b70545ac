// The portable transcendental functions: close to the C library's everywhere the simulation uses
// them, and exact where IEEE defines special values. That they give the same bits on every machine
// is checked across machines by tests/release (libraries compared byte for byte).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

#include "common/PortableMath.h"

namespace mwb {
namespace {

namespace pm = mwb::portable;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Distance in units in the last place, for finite values of one sign.
int64_t ulps_apart(double a, double b) {
    if (a == b) return 0;
    int64_t ia, ib;
    std::memcpy(&ia, &a, 8);
    std::memcpy(&ib, &b, 8);
    if ((ia < 0) != (ib < 0)) return std::numeric_limits<int64_t>::max();
    return ia > ib ? ia - ib : ib - ia;
}

/// Worst error against the C library over random arguments in [lo, hi], in ulps of the result,
/// with an absolute floor of `abs_floor` for results near zero.
template <typename F, typename G>
double worst_error(F ours, G reference, double lo, double hi, double abs_floor = 0.0) {
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> arg(lo, hi);
    double worst = 0;
    for (int i = 0; i < 200000; ++i) {
        const double x = arg(random);
        const double a = ours(x), b = reference(x);
        const double ulp = std::nextafter(std::fabs(b), kInf) - std::fabs(b);
        worst = std::max(worst, std::fabs(a - b) / std::max(ulp, abs_floor));
    }
    return worst;
}

TEST(PortableMath, SinAndCosStayWithinTwoUlpsOfTheCLibraryOverManyTurns) {
    EXPECT_LE(worst_error(pm::sin, [](double x) { return std::sin(x); }, -100, 100, 1e-300), 2.0);
    EXPECT_LE(worst_error(pm::cos, [](double x) { return std::cos(x); }, -100, 100, 1e-300), 2.0);
    EXPECT_LE(worst_error(pm::sin, [](double x) { return std::sin(x); }, -0.8, 0.8), 2.0);
    // Results near zero (x near k pi) are judged against the result's scale, 1.
    EXPECT_LE(worst_error(pm::sin, [](double x) { return std::sin(x); }, 1e3, 4e5, 1e-16), 4.0);
}

TEST(PortableMath, InverseTrigonometryStaysWithinThreeUlps) {
    EXPECT_LE(worst_error(pm::asin, [](double x) { return std::asin(x); }, -1, 1), 3.0);
    EXPECT_LE(worst_error(pm::acos, [](double x) { return std::acos(x); }, -1, 1), 3.0);
    std::mt19937_64 random(3);
    std::uniform_real_distribution<double> arg(-10, 10);
    for (int i = 0; i < 200000; ++i) {
        const double y = arg(random), x = arg(random);
        EXPECT_LE(ulps_apart(pm::atan2(y, x), std::atan2(y, x)), 2) << y << " " << x;
    }
}

TEST(PortableMath, ExpLogAndPowStayWithinAFewUlps) {
    EXPECT_LE(worst_error(pm::exp, [](double x) { return std::exp(x); }, -700, 700), 2.0);
    EXPECT_LE(worst_error(pm::log, [](double x) { return std::log(x); }, 1e-300, 1e300, 1e-16), 2.0);
    EXPECT_LE(worst_error(pm::log, [](double x) { return std::log(x); }, 0.5, 2.0, 1e-16), 2.0);
    // The damping factor (1 - d)^dt and the perturbation lobe u^(1/(n+1)).
    EXPECT_LE(worst_error([](double d) { return pm::pow(1 - d, 1.0 / 240); },
                          [](double d) { return std::pow(1 - d, 1.0 / 240); }, 0, 0.99), 4.0);
    EXPECT_LE(worst_error([](double u) { return pm::pow(u, 1.0 / 31); },
                          [](double u) { return std::pow(u, 1.0 / 31); }, 1e-9, 1), 4.0);
    EXPECT_LE(ulps_apart(pm::hypot(3e200, 4e200), 5e200), 1);
}

TEST(PortableMath, SpecialValuesFollowIeee) {
    EXPECT_TRUE(std::signbit(pm::sin(-0.0)));
    EXPECT_EQ(pm::cos(0.0), 1.0);
    EXPECT_TRUE(std::isnan(pm::sin(kInf)));
    EXPECT_TRUE(std::isnan(pm::cos(kNaN)));
    EXPECT_EQ(pm::atan2(0.0, -1.0), pm::atan2(0.0, -0.0));
    EXPECT_DOUBLE_EQ(pm::atan2(0.0, -1.0), M_PI);
    EXPECT_TRUE(std::signbit(pm::atan2(-0.0, 1.0)));
    EXPECT_DOUBLE_EQ(pm::atan2(-1.0, 0.0), -M_PI / 2);
    EXPECT_DOUBLE_EQ(pm::atan2(kInf, -kInf), 3 * M_PI / 4);
    EXPECT_EQ(pm::acos(1.0), 0.0);
    EXPECT_DOUBLE_EQ(pm::acos(-1.0), M_PI);
    EXPECT_DOUBLE_EQ(pm::asin(1.0), M_PI / 2);
    EXPECT_TRUE(std::isnan(pm::asin(1.0000001)));
    EXPECT_EQ(pm::exp(0.0), 1.0);
    EXPECT_EQ(pm::exp(-kInf), 0.0);
    EXPECT_EQ(pm::exp(1000.0), kInf);
    EXPECT_EQ(pm::log(1.0), 0.0);
    EXPECT_EQ(pm::log(0.0), -kInf);
    EXPECT_TRUE(std::isnan(pm::log(-1.0)));
    EXPECT_EQ(pm::pow(-2.0, 3.0), -8.0 * (pm::pow(2.0, 3.0) / 8.0));
    EXPECT_TRUE(std::isnan(pm::pow(-2.0, 0.5)));
    EXPECT_EQ(pm::pow(0.0, -1.0), kInf);
    EXPECT_EQ(pm::pow(kNaN, 0.0), 1.0);
    EXPECT_EQ(pm::pow(-kInf, 3.0), -kInf);
    EXPECT_EQ(pm::pow(0.5, kInf), 0.0);
}

}  // namespace
}  // namespace mwb
