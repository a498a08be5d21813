# picomis: single-precision soft float for RV32IMC (no F extension), see mod.rs.
# The linker's --wrap (build.rs) sends the compiler's calls to __addsf3, __subsf3, __mulsf3 and
# the comparisons here; __real___addsf3 / __real___mulsf3 are compiler-builtins' routines, which
# take the cases off the fast paths with the original operands. C calling convention: operands
# in a0, a1, result in a0; only caller-saved registers are written; no stack.
# Round to nearest, ties to even.

    .option push
    .option arch, +m            # mulhu (fat LTO assembles this without the target's features)

# ---------------------------------------------------------------------------------------------
# The sum of two normal operands of which X has the larger magnitude, XX = |X| << 1 and
# YY = |Y| << 1 (XX >= YY); the result in a0, or to .Lfadd_lib with a0, a1 as they came in.
# Significands with their leading one at bit 31, the smaller shifted right with a sticky bit at
# bit 0: eight bits below the last kept one, enough to round a sum and a difference (which needs
# at most one bit of normalization when anything was shifted out).
.macro FADD_BODY X, Y, XX, YY
    srli t2, \XX, 24            # ex
    srli t3, \YY, 24            # ey
    beqz t3, .Lfadd_lib         # the smaller is subnormal
    sub t3, t2, t3              # d = ex - ey >= 0
    lui t6, 0x80000
    slli t4, \X, 8
    or t4, t4, t6               # mx = 1.fx at bits 31..8
    slli t5, \Y, 8
    or t5, t5, t6               # my
    and a5, \X, t6              # the result's sign: the larger's (unless it cancels to +0)
    xor a4, \X, \Y              # bit 31: the signs differ (magnitudes subtract)
    li a2, 31
    bltu t3, a2, 1f
    mv t3, a2                   # my >> 31 = 1: only the sticky bit is left
1:  srl a2, t5, t3
    sll a3, a2, t3
    sltu a3, a3, t5             # 1 when bits were shifted out
    or t5, a2, a3               # my >> d, sticky bit at bit 0
    bltz a4, 3f
    add t4, t4, t5
    bgeu t4, t5, .Lfadd_round   # no carry out of bit 31
    andi a3, t4, 1              # carry: one bit right, keeping the sticky bit, exponent ex + 1
    srli t4, t4, 1
    or t4, t4, a3
    or t4, t4, t6
    addi t2, t2, 1
    j .Lfadd_round
3:  sub t4, t4, t5              # >= 0, since |x| >= |y|
    beqz t4, .Lfadd_zero        # x - x = +0
    bltz t4, .Lfadd_round
4:  slli t4, t4, 1              # cancellation: normalize one bit at a time
    addi t2, t2, -1
    bgez t4, 4b
    j .Lfadd_round
.endm

# float __wrap___subsf3(float a, float b) = a + (-b), which is how compiler-builtins computes it
    .section .text.picomis_rv_fadd,"ax",@progbits
    .globl __wrap___subsf3
    .type __wrap___subsf3, @function
    .globl __wrap___addsf3
    .type __wrap___addsf3, @function
    .balign 2
__wrap___subsf3:
    lui t0, 0x80000
    xor a1, a1, t0
    # falls through into __wrap___addsf3

# float __wrap___addsf3(float a, float b)
__wrap___addsf3:
    slli t0, a0, 1              # |a| << 1
    slli t1, a1, 1              # |b| << 1
    beqz t1, .Lfadd_bzero
    beqz t0, .Lfadd_azero
    lui t6, 0xff000             # |x| << 1 of infinity
    bgeu t0, t6, .Lfadd_lib     # a infinite or NaN
    bgeu t1, t6, .Lfadd_lib     # b infinite or NaN
    bltu t0, t1, .Lfadd_swapped
    FADD_BODY a0, a1, t0, t1
.Lfadd_swapped:
    FADD_BODY a1, a0, t1, t0
# t4: the significand with its leading one at bit 31 (24 bits kept, 8 below), t2: the biased
# exponent, a5: the sign.
.Lfadd_round:
    addi t3, t2, -1
    li a3, 253
    bgtu t3, a3, .Lfadd_lib     # subnormal or overflowing result
    slli t3, t3, 23             # (e - 1) << 23: the leading one adds the last 1
    srli a3, t4, 8
    add a3, a3, t3
    or a0, a5, a3               # sign | exponent | fraction, truncated
    andi t3, t4, 0xff           # round bit (7) and sticky bits
    andi a3, a3, 1
    add t3, t3, a3              # above 0x80: round up (more than half, or half and odd)
    addi t3, t3, 0x7f
    srli t3, t3, 8
    add a0, a0, t3              # a carry into the exponent is right, up to infinity
    ret
.Lfadd_zero:
    li a0, 0
    ret
.Lfadd_bzero:
    bnez t0, 1f
    and a0, a0, a1              # 0 + 0: -0 only when both are -0
    ret
1:  lui t6, 0xff000
    bltu t6, t0, .Lfadd_lib     # NaN + 0: the library (it quiets the NaN)
    ret                         # a + 0 = a
.Lfadd_azero:
    lui t6, 0xff000
    bltu t6, t1, .Lfadd_lib     # 0 + NaN
    mv a0, a1                   # 0 + b = b
    ret
.Lfadd_lib:
    tail __real___addsf3
    .size __wrap___addsf3, . - __wrap___addsf3
    .size __wrap___subsf3, . - __wrap___subsf3

# ---------------------------------------------------------------------------------------------
# float __wrap___mulsf3(float a, float b)
    .section .text.picomis_rv_fmul,"ax",@progbits
    .globl __wrap___mulsf3
    .type __wrap___mulsf3, @function
    .balign 2
__wrap___mulsf3:
    slli t0, a0, 1
    slli t1, a1, 1
    beqz t0, .Lfmul_azero
    beqz t1, .Lfmul_bzero
    srli t2, t0, 24
    srli t3, t1, 24
    addi t2, t2, -1             # ea - 1, in 0..=253 for a normal a
    addi t3, t3, -1
    li a3, 253
    bgtu t2, a3, .Lfmul_lib     # a subnormal, infinite or NaN
    bgtu t3, a3, .Lfmul_lib
    add t2, t2, t3
    lui t6, 0x80000
    slli t4, a0, 8
    or t4, t4, t6               # 1.fa at bits 31..8
    slli t5, a1, 8
    or t5, t5, t6
    mulhu t3, t4, t5            # the product's top 32 bits: leading one at bit 31 or 30
    mul t4, t4, t5              # the low 32: sticky bits
    xor a2, a0, a1
    and a2, a2, t6              # the product's sign
    addi t2, t2, -125           # e - 1 for a product of significands in [2, 4)
    bltz t3, 1f
    slli t3, t3, 1              # in [1, 2): one binade lower (bit 0 joins the sticky bits)
    addi t2, t2, -1
1:  bgtu t2, a3, .Lfmul_lib     # subnormal or overflowing product
    slli t2, t2, 23
    srli a3, t3, 8
    add a3, a3, t2
    or a0, a2, a3               # sign | exponent | fraction, truncated
    andi t2, t3, 0xff           # round bit (7) and sticky bits
    snez t4, t4
    or t2, t2, t4
    andi a3, a3, 1
    add t2, t2, a3              # above 0x80: round up
    addi t2, t2, 0x7f
    srli t2, t2, 8
    add a0, a0, t2
    ret
.Lfmul_azero:
    lui t6, 0xff000
    bgeu t1, t6, .Lfmul_lib     # 0 * inf, 0 * NaN: the library (NaN)
    j 2f
.Lfmul_bzero:
    lui t6, 0xff000
    bgeu t0, t6, .Lfmul_lib
2:  xor a0, a0, a1              # 0 * finite = signed 0
    srli a0, a0, 31
    slli a0, a0, 31
    ret
.Lfmul_lib:
    tail __real___mulsf3
    .size __wrap___mulsf3, . - __wrap___mulsf3

# ---------------------------------------------------------------------------------------------
# The comparisons, as compiler-builtins defines them: -1, 0 or 1 for less, equal (+0 == -0) or
# greater; unordered (a NaN operand) gives 1 for __lesf2, __ltsf2, __eqsf2 and __nesf2, and -1
# for __gesf2 and __gtsf2; __unordsf2 is 1 when either is a NaN, else 0. Both operands
# non-negative (the common case): their bits order them as unsigned integers. Otherwise keys
# k(x) = x ^ ((x asr 31) lsr 1) order them as signed integers, except -0 < +0.
.macro FCMP name, unordered
    .section .text.picomis_rv_\name,"ax",@progbits
    .globl __wrap___\name
    .type __wrap___\name, @function
    .balign 2
__wrap___\name:
    lui t2, 0x7f800             # +inf
    or t3, a0, a1
    bltz t3, 1f                 # a sign bit is set
    bltu t2, a0, 8f             # a is a NaN
    bltu t2, a1, 8f
    sltu t0, a0, a1
    sltu a0, a1, a0
    sub a0, a0, t0              # (a > b) - (a < b)
    ret
1:  slli t0, a0, 1
    slli t1, a1, 1
    srli t0, t0, 1              # |a|
    srli t1, t1, 1
    bltu t2, t0, 8f             # a is a NaN
    bltu t2, t1, 8f
    or t3, t0, t1
    beqz t3, 9f                 # +-0 and +-0: equal
    srai t0, a0, 31
    srli t0, t0, 1
    xor t0, t0, a0
    srai t1, a1, 31
    srli t1, t1, 1
    xor t1, t1, a1
    slt t2, t0, t1
    slt a0, t1, t0
    sub a0, a0, t2
    ret
8:  li a0, \unordered
    ret
9:  li a0, 0
    ret
    .size __wrap___\name, . - __wrap___\name
.endm

    FCMP lesf2, 1
    FCMP ltsf2, 1
    FCMP eqsf2, 1
    FCMP nesf2, 1
    FCMP gesf2, -1
    FCMP gtsf2, -1

# int __wrap___unordsf2(float a, float b)
    .section .text.picomis_rv_unordsf2,"ax",@progbits
    .globl __wrap___unordsf2
    .type __wrap___unordsf2, @function
    .balign 2
__wrap___unordsf2:
    lui t2, 0xff000             # |x| << 1 of infinity
    slli t0, a0, 1
    slli t1, a1, 1
    sltu t0, t2, t0
    sltu t1, t2, t1
    or a0, t0, t1
    ret
    .size __wrap___unordsf2, . - __wrap___unordsf2

    .option pop
