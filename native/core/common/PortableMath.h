#pragma once
// Transcendental functions whose results are the same on every machine. The C library's sin, cos,
// atan2, pow, ... are not correctly rounded, and their last bits have changed between glibc
// versions, so a world simulated with them could differ between a farm node and a workstation.
// These use only IEEE-754 addition, multiplication, division, sqrt and exact scaling (compiled
// without contraction into fused multiply-adds), which every x86-64 machine rounds the same way.
// Accuracy: within a few units in the last place over the ranges the simulation uses.
//
// ODE and libccd, built by native/ode, call these too: their references to the C library's
// functions are renamed to the mwb_portable_* symbols below (native/ode/portable-math.syms).

namespace mwb::portable {

double sin(double x);
double cos(double x);
void sincos(double x, double* sin_x, double* cos_x);
double atan2(double y, double x);
double asin(double x);
double acos(double x);
double exp(double x);
double log(double x);
double pow(double x, double y);
double hypot(double x, double y);

}  // namespace mwb::portable

extern "C" {
double mwb_portable_sin(double x);
double mwb_portable_cos(double x);
void mwb_portable_sincos(double x, double* sin_x, double* cos_x);
double mwb_portable_atan2(double y, double x);
double mwb_portable_asin(double x);
double mwb_portable_acos(double x);
float mwb_portable_sinf(float x);
float mwb_portable_cosf(float x);
void mwb_portable_sincosf(float x, float* sin_x, float* cos_x);
float mwb_portable_atan2f(float y, float x);
float mwb_portable_asinf(float x);
float mwb_portable_acosf(float x);
double mwb_portable_exp(double x);
double mwb_portable_log(double x);
double mwb_portable_pow(double x, double y);
}
