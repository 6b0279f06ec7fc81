#!/usr/bin/env bash
# tools/check_no_float.sh BUILD_DIR
#
# The proof that fixed/ and core/ hold no floating point, read from the code
# that ships: every object of the bitstep_fixed and bitstep_core libraries in
# BUILD_DIR is disassembled (objdump) and its undefined symbols listed (nm),
# and any floating-point instruction or reference fails the check, one line
# each (object, function, instruction). Reading the objects, rather than
# keeping the compiler off the vector registers, leaves core/ free to use
# integer SIMD and checks what the compiler made of every source under the
# build's own flags. x86 objects only (the rules below are x86 mnemonics).
#
# Flagged (Intel-syntax mnemonics, prefixes such as rep or lock removed):
#   - x87 and AVX float: every mnemonic starting with f or vf (fld, fstp,
#     fild, fucomip, fnstcw, vfmadd231sd, vfnmsub..., vfpclassps), but for
#     fxsave/fxrstor (save the register state; they compute nothing);
#   - conversions to or from float: every mnemonic starting with cvt or vcvt
#     (cvtsi2sd, cvttsd2si, cvtdq2pd, vcvtph2ps, ...);
#   - SSE/AVX float arithmetic: v? + one of add sub mul div sqrt min max
#     cmp* comi ucomi rcp rsqrt (with 14/28) round rndscale dp dpbf16 hadd
#     hsub addsub getexp getmant scalef reduce range fixupimm exp2 + one of
#     ss sd sh ps pd ph (addsd, vmulps, cmpltsd, vcmpeq_oqps, ucomisd,
#     roundsd, ...); pminsd and the like start with p and do not match;
#   - ldmxcsr/stmxcsr: the float rounding and exception modes;
#   - a function whose (demangled) signature names float, double, long
#     double, _FloatN, __float128, __bf16 or __fp16, defined in the object or
#     called from it: a double passed through untouched needs no flagged
#     instruction, only a movsd;
#   - an undefined reference to libm (sqrt, sin, pow, floor, sincos, ... with
#     an f or l suffix, or glibc's __*_finite) or to libgcc's soft float
#     (__adddf3, __floatsidf, __fixdfsi, __extendsfdf2, __muldc3, ...).
# Allowed: moves, shuffles, blends and bitwise operations on xmm/ymm
# registers, whatever their type suffix (movaps, movups, movss, movsd, movq,
# movd, shufps, unpcklps, blendvps, movmskps, xorps, andnps, orpd, ...). They
# copy or combine bits exactly, as integer code does: compilers use them to
# copy and zero memory (xorps to clear a register), and integer SIMD needs
# them. Any float computation needs a flagged instruction or call.
#
# Exit status: 0 clean (one summary line), 1 floating point found, 2 the
# check could not run (no objects, no binutils, a non-x86 object).
set -euo pipefail

build=${1:?usage: tools/check_no_float.sh BUILD_DIR}
for tool in objdump nm; do
  command -v "$tool" >/dev/null || { echo "check_no_float.sh: $tool not found (binutils)" >&2; exit 2; }
done

objects=()
for target in bitstep_fixed bitstep_core; do
  mapfile -t found < <(find "$build/CMakeFiles/$target.dir" -name '*.o' 2>/dev/null | sort)
  if [ ${#found[@]} -eq 0 ]; then
    echo "check_no_float.sh: no objects of $target under $build/CMakeFiles/$target.dir (build it first)" >&2
    exit 2
  fi
  objects+=("${found[@]}")
done

# Both listings go through one awk, nm's after a marker line. awk checks that
# every object was disassembled and that nm's part arrived, so a failing
# objdump or nm cannot pass for a clean library.
{
  objdump -d --no-show-raw-insn -C -M intel "${objects[@]}"
  echo '@@ nm'
  nm -A -u -C "${objects[@]}"
} | awk -F '\t' -v expected="${#objects[@]}" '
function float_type(name) {
  return name ~ /(^|[^A-Za-z0-9_])(float|double|_Float[0-9]+x?|__float128|__ibm128|__ieee128|__bf16|__fp16)([^A-Za-z0-9_]|$)/
}
function flag(object, where, what) {
  print object ": " where ": " what
  found++
}
BEGIN {
  libm = "sqrt|cbrt|hypot|exp|exp2|expm1|log|log2|log10|log1p|pow|sin|cos|tan|sincos|asin|acos|atan|atan2|" \
         "sinh|cosh|tanh|asinh|acosh|atanh|floor|ceil|trunc|round|lround|llround|rint|lrint|llrint|" \
         "nearbyint|fmod|remainder|remquo|modf|frexp|ldexp|scalbn|scalbln|ilogb|logb|fabs|fmin|fmax|fdim|" \
         "fma|copysign|nextafter|erf|erfc|tgamma|lgamma"
}
$0 == "@@ nm" { in_nm = 1; next }

# objdump: "path.o:     file format elf64-x86-64"
!in_nm && / file format / {
  object = $0
  sub(/: +file format .*/, "", object)
  if ($0 !~ /file format (elf64-x86-64|elf32-i386|elf32-x86-64)$/) {
    print "check_no_float.sh: " $0 ": not an x86 object (the rules are x86 mnemonics)" > "/dev/stderr"
    status = 2
    exit
  }
  objects++
  next
}
# objdump: "0000000000000000 <bitstep::sqrt(bitstep::Fixed)>:"
!in_nm && /^[0-9a-f]+ <.*>:$/ {
  function_name = $0
  sub(/^[0-9a-f]+ </, "", function_name)
  sub(/>:$/, "", function_name)
  if (float_type(function_name)) flag(object, function_name, "float type in the signature")
  next
}
# objdump: "  1f:<TAB>addsd  xmm0,xmm1"
!in_nm && /^ *[0-9a-f]+:\t/ {
  instructions++
  n = split($2, word, " ")
  i = 1
  while (i < n && word[i] ~ /^(rep[a-z]*|lock|cs|ds|es|fs|gs|ss|data16|data32|addr16|addr32|notrack|bnd|xacquire|xrelease|rex(\.[A-Z]+)?|\{[a-z0-9]+\})$/) i++
  m = word[i]
  if ((m ~ /^v?f/ && m !~ /^fx(save|rstor)(64)?$/) ||
      m ~ /^v?cvt/ ||
      m ~ /^v?(add|sub|mul|div|sqrt|min|max|cmp[a-z_]*|u?comi|rcp(14|28)?|rsqrt(14|28)?|round|rndscale|dp|dpbf16|hadd|hsub|addsub|getexp|getmant|scalef|reduce|range|fixupimm|exp2)(ss|sd|sh|ps|pd|ph)$/ ||
      m ~ /^v?(ld|st)mxcsr$/) {
    text = $2
    sub(/ *(#.*)?$/, "", text)
    gsub(/  +/, " ", text)
    flag(object, function_name, text)
  }
  next
}
# nm -A -u: "path.o:                 U memcpy"
in_nm && match($0, /:[ \t]+U /) {
  symbols++
  object = substr($0, 1, RSTART - 1)
  symbol = substr($0, RSTART + RLENGTH)
  if (symbol ~ ("^(" libm ")(f|l|f128)?$") || symbol ~ ("^__(" libm ")(f|l)?_finite$"))
    flag(object, "undefined reference", symbol " (libm)")
  else if (symbol ~ /^__((add|sub|mul|div|neg|cmp|eq|ne|lt|le|gt|ge|unord|powi)(sf|df|tf|xf|hf|bf)[23]|float(un)?(si|di|ti)(sf|df|tf|xf|hf|bf)|fix(uns)?(sf|df|tf|xf|hf|bf)(si|di|ti)|(extend|trunc)(sf|df|tf|xf|hf|bf)(sf|df|tf|xf|hf|bf)2|(mul|div)(sc|dc|tc|xc|hc)3)$/)
    flag(object, "undefined reference", symbol " (soft float)")
  else if (float_type(symbol))
    flag(object, "undefined reference", symbol " (float type in the signature)")
}
END {
  if (status) exit status
  if (!in_nm || objects != expected) {
    print "check_no_float.sh: objdump or nm failed (" objects + 0 " of " expected " objects read)" > "/dev/stderr"
    exit 2
  }
  summary = objects " objects of bitstep_fixed and bitstep_core, " instructions + 0 " instructions and " symbols + 0 " undefined symbols"
  if (found) {
    fflush()
    print "check_no_float.sh: " found " floating-point instructions or references in " summary > "/dev/stderr"
    exit 1
  }
  print "check_no_float.sh: no floating point in " summary
}'
