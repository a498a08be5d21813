# picomis: single-precision soft float for RV32IMC (no F extension), see lib.rs.
# The linker's --wrap (lib.rs: RV32_WRAPPED) sends the compiler's calls to __addsf3, __subsf3,
# __mulsf3 and the comparisons here; picomis_fadd_slow and the like (slow.rs) take the cases off
# the fast paths with the original operands. C calling
# convention: operands in a0, a1, result in a0; only caller-saved registers are written; no stack.
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
    tail picomis_fadd_slow
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
    tail picomis_fmul_slow
    .size __wrap___mulsf3, . - __wrap___mulsf3

# ---------------------------------------------------------------------------------------------
# float __wrap___divsf3(float a, float b): the algorithm of m0.s's __aeabi_fdiv, step for step
# (the same 128-entry reciprocal table, Newton step, two digit steps and one correction, each
# product and remainder modulo 2^32 as MULS computes them there), so the error bound that
# tools/tests/fdiv_bound.rs proves for that routine holds here too. With A = 1.fa and
# B = 1.fb as 24-bit integers (A doubled when A < B), Q' = floor(A 2^24 / B) has 25 bits and is
# never exactly halfway, so rounding to nearest is (Q' + 1) >> 1.
    .section .text.picomis_rv_fdiv,"ax",@progbits
    .globl __wrap___divsf3
    .type __wrap___divsf3, @function
    .balign 2
__wrap___divsf3:
    slli t0, a0, 1
    slli t1, a1, 1
    srli t2, t0, 24
    srli t3, t1, 24
    addi t3, t3, -1             # eb - 1 (b zero, subnormal, infinite or NaN: the library)
    li a3, 253
    bgtu t3, a3, .Lfdiv_lib
    addi t2, t2, -1             # ea - 1
    bgtu t2, a3, .Lfdiv_aspecial
    sub t2, t2, t3              # ea - eb
    lui t6, 0x800               # 2^23, the implicit one
    slli t4, a0, 9
    srli t4, t4, 9
    or t4, t4, t6               # A = 1.fa
    slli t5, a1, 9
    srli t5, t5, 9
    or t5, t5, t6               # B = 1.fb, in [2^23, 2^24)
    xor a2, a0, a1
    srli a2, a2, 31
    slli a2, a2, 31             # the quotient's sign
    bgeu t4, t5, 1f
    slli t4, t4, 1              # A < B: 2A, in (B, 2B), and the exponent one lower
    addi t2, t2, -1
1:  addi t2, t2, 126            # e - 1, e = ea - eb + 127 the result's biased exponent
    bgtu t2, a3, .Lfdiv_lib     # subnormal or overflowing result
    srli t0, t5, 16             # 128 + i
    slli t0, t0, 1
    la t1, .Lfdiv_recip
    add t0, t0, t1
    lhu t0, -256(t0)            # X0 = 2^24 / (257 + 2i)
    srli t1, t5, 8
    addi t1, t1, 1              # b16, in (2^15, 2^16]
    mul t1, t0, t1              # P = X0 b16 < 2^32
    lui t3, 0x80000
    sub t1, t3, t1              # E = 2^31 - P, |E| < 2^23
    srai t1, t1, 8
    mul t1, t0, t1
    srai t1, t1, 23
    add t0, t0, t1              # X <= 2^39 / B
    srli t1, t4, 9
    mul t1, t1, t0
    srli t1, t1, 16             # q1 = floor((A >> 9) X / 2^16) < 2^15
    slli t3, t4, 14
    mul a4, t1, t5
    sub t3, t3, a4              # r1 = A 2^14 - q1 B, in [0, 2^27): exact mod 2^32
    srli a4, t3, 11
    mul a4, a4, t0
    srli a4, a4, 18             # q2
    slli t1, t1, 10
    add t1, t1, a4              # Q = q1 2^10 + q2 <= Q'
    mul a4, a4, t5
    slli t3, t3, 10
    sub t3, t3, a4              # R = A 2^24 - Q B, in [0, 2B): exact mod 2^32
    sltu a4, t3, t5             # R < B: Q' = Q, else Q + 1
    sub t1, t1, a4
    addi t1, t1, 2              # Q' + 1
    srli t1, t1, 1              # 1.f in [2^23, 2^24]: 2^24 carries into the exponent, up to infinity
    slli t2, t2, 23
    add t1, t1, t2
    or a0, a2, t1
    ret
.Lfdiv_aspecial:
    bnez t0, .Lfdiv_lib         # a subnormal, infinite or NaN
    xor a0, a0, a1              # 0 / normal = signed 0
    srli a0, a0, 31
    slli a0, a0, 31
    ret
.Lfdiv_lib:
    tail picomis_fdiv_slow
    .size __wrap___divsf3, . - __wrap___divsf3

    .section .rodata.picomis_rv_fdiv,"a",@progbits
    .balign 2
.Lfdiv_recip:
    FDIV_RECIPROCALS            # fdiv_recip.s

# ---------------------------------------------------------------------------------------------
# float __wrap___floatunsisf(unsigned a): rounded to nearest, ties to even. The leading one is
# moved to bit 31 in steps of 16, 8, 4, 2 and 1 (RV32IMC has no count of leading zeros), then
# packed and rounded like the other routines. Complete: no case for the library.
# float __wrap___floatsisf(int a): the same on |a| (-2^31 is 2^31 unsigned), with a's sign.
    .section .text.picomis_rv_ui2f,"ax",@progbits
    .globl __wrap___floatunsisf, __wrap___floatsisf
    .type __wrap___floatunsisf, @function
    .type __wrap___floatsisf, @function
    .balign 2
__wrap___floatsisf:
    srli a1, a0, 31
    slli a1, a1, 31             # the sign
    bgez a0, 0f
    neg a0, a0
    j 0f
__wrap___floatunsisf:
    li a1, 0                    # the sign: +
0:  beqz a0, 9f                 # 0 -> +0
    li t0, 157                  # e - 1 for a leading one at bit 31 (e = 127 + 31)
    srli t1, a0, 16
    bnez t1, 1f
    slli a0, a0, 16
    addi t0, t0, -16
1:  srli t1, a0, 24
    bnez t1, 2f
    slli a0, a0, 8
    addi t0, t0, -8
2:  srli t1, a0, 28
    bnez t1, 3f
    slli a0, a0, 4
    addi t0, t0, -4
3:  srli t1, a0, 30
    bnez t1, 4f
    slli a0, a0, 2
    addi t0, t0, -2
4:  bltz a0, 5f
    slli a0, a0, 1
    addi t0, t0, -1
5:  srli t1, a0, 8              # 1.f, 24 bits
    slli t0, t0, 23
    add t1, t1, t0              # exponent | fraction, truncated
    andi t2, a0, 0xff           # round bit (7) and sticky bits
    andi t3, t1, 1
    add t2, t2, t3              # above 0x80: round up
    addi t2, t2, 0x7f
    srli t2, t2, 8
    add a0, t1, t2
9:  or a0, a0, a1
    ret
    .size __wrap___floatsisf, . - __wrap___floatsisf
    .size __wrap___floatunsisf, . - __wrap___floatunsisf

# ---------------------------------------------------------------------------------------------
# The comparisons, as compiler-builtins defines them: -1, 0 or 1 for less, equal (+0 == -0) or
# greater; unordered (a NaN operand) gives 1 for __lesf2, __ltsf2, __eqsf2 and __nesf2, and -1
# for __gesf2 and __gtsf2; __unordsf2 is 1 when either is a NaN, else 0. Both operands
# non-negative (the common case): their bits order them as unsigned integers. Otherwise keys
# k(x) = x ^ ((x asr 31) lsr 1) order them as signed integers, except -0 < +0.
# One body for the six: __gesf2 and __gtsf2 enter with -1 for unordered in a2, the other four
# (the same code) with 1.
    .section .text.picomis_rv_fcmp,"ax",@progbits
    .globl __wrap___gesf2, __wrap___gtsf2
    .globl __wrap___lesf2, __wrap___ltsf2, __wrap___eqsf2, __wrap___nesf2
    .type __wrap___gesf2, @function
    .type __wrap___gtsf2, @function
    .type __wrap___lesf2, @function
    .type __wrap___ltsf2, @function
    .type __wrap___eqsf2, @function
    .type __wrap___nesf2, @function
    .balign 2
__wrap___gesf2:
__wrap___gtsf2:
    li a2, -1
    j 0f
__wrap___lesf2:
__wrap___ltsf2:
__wrap___eqsf2:
__wrap___nesf2:
    li a2, 1
0:  lui t2, 0x7f800             # +inf
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
8:  mv a0, a2                   # unordered
    ret
9:  li a0, 0
    ret
    .size __wrap___gesf2, . - __wrap___gesf2
    .size __wrap___gtsf2, . - __wrap___gtsf2
    .size __wrap___lesf2, . - __wrap___lesf2
    .size __wrap___ltsf2, . - __wrap___ltsf2
    .size __wrap___eqsf2, . - __wrap___eqsf2
    .size __wrap___nesf2, . - __wrap___nesf2

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
