// Floating point planted for tests/tools/check_no_float_test.sh: a double
// multiply (mulsd), an int -> double conversion (cvtsi2sd) and std::sqrt
// (an undefined reference to libm's sqrt, which -O2 keeps for errno).
// tools/check_no_float.sh must name each of them. Not part of any library.
#include <cmath>

double planted_product(double a, double b) { return a * b; }
double planted_conversion(int n) { return static_cast<double>(n); }
double planted_root(double x) { return std::sqrt(x); }
