# picomis: the dot product of two 3-vectors for soft-float RV32 (RV32IMC), see dot3.rs.
#
# u64 picomis_dot3(u32 ax, u32 ay, u32 az, u32 bx, u32 by, u32 bz)
#   a0: the bits of ((ax bx + ay by) + az bz), each product and sum rounded to nearest, ties to
#       even, as the separate f32 operations round them; a1: 1 when a0 holds it, 0 when the
#       operands or a step are outside the fast path (an operand infinite, NaN or subnormal
#       times non-zero; a product or sum subnormal or overflowing): the caller then computes it
#       with the library's routines.
# The products and the partial sum stay unpacked between the steps: sign (bit 31 of a register,
# the rest zero), biased exponent (0 for a zero value) and significand (24 bits, leading one at
# bit 23).

    .option push
    .option arch, +m            # the multiplies (fat LTO assembles this without the target's features)
    .section .text.picomis_dot3,"ax",@progbits
    .globl picomis_dot3
    .type picomis_dot3, @function
    .balign 4

# \x, \y: the operands' bits. Out: \x = sign, \y = biased exponent (0: the product is zero),
# \sig = significand. Clobbers t3, t4, t5; t6 = 253.
.macro PRODUCT x, y, sig
    slli t3, \x, 1
    slli t4, \y, 1
    beqz t3, 81f                # x = +-0
    beqz t4, 82f                # y = +-0 (x is not)
    srli t3, t3, 24             # ex
    srli t4, t4, 24             # ey
    addi t5, t3, -1
    bgtu t5, t6, .Lslow         # x subnormal, infinite or NaN
    addi t5, t4, -1
    bgtu t5, t6, .Lslow
    add t3, t3, t4              # ex + ey
    slli t4, \x, 8
    slli t5, \y, 8
    xor \x, \x, \y
    lui \y, 0x80000
    or t4, t4, \y               # 1.fx at bits 31..8
    or t5, t5, \y               # 1.fy
    and \x, \x, \y              # the product's sign
    mulhu \sig, t4, t5          # the product's top 32 bits: leading one at bit 31 or 30
    mul t4, t4, t5              # the low 32: sticky bits
    bltz \sig, 83f
    slli \sig, \sig, 1          # in [1, 2): one binade lower (bit 0 joins the sticky bits)
    addi t3, t3, -1
83: addi \y, t3, -126           # the biased exponent before rounding
    andi t3, \sig, 0xff         # round bit (7) and sticky bits
    snez t4, t4
    or t3, t3, t4
    srli \sig, \sig, 8          # 24 bits
    andi t4, \sig, 1
    add t3, t3, t4              # above 0x80: round up (more than half, or half and odd)
    addi t3, t3, 0x7f
    srli t3, t3, 8
    add \sig, \sig, t3
    srli t3, \sig, 24           # rounded up to 2^24: 2^23 and one more in the exponent
    srl \sig, \sig, t3
    add \y, \y, t3
    addi t3, \y, -1
    bgtu t3, t6, .Lslow         # subnormal or overflowing product
    j 84f
81: srli t4, t4, 24             # 0 * y: y must be finite
    addi t4, t4, -255
    beqz t4, .Lslow
    j 85f
82: srli t3, t3, 24             # x * 0: x must be finite
    addi t3, t3, -255
    beqz t3, .Lslow
85: xor \x, \x, \y
    srli \x, \x, 31
    slli \x, \x, 31             # a signed zero
    li \y, 0
    li \sig, 0
84:
.endm

# (\s1, \e1, \m1) += (\s2, \e2, \m2), rounded. Clobbers the second operand, t3, t4, t5.
.macro ADD s1, e1, m1, s2, e2, m2
    beqz \e2, 91f               # + 0
    beqz \e1, 92f               # 0 + y = y
    slli t3, \e1, 24            # magnitudes as keys: exponent above significand
    or t3, t3, \m1
    slli t4, \e2, 24
    or t4, t4, \m2
    bgeu t3, t4, 93f
    mv t3, \s1                  # |x| < |y|: exchange them
    mv \s1, \s2
    mv \s2, t3
    mv t3, \e1
    mv \e1, \e2
    mv \e2, t3
    mv t3, \m1
    mv \m1, \m2
    mv \m2, t3
93: sub t3, \e1, \e2            # d >= 0
    slli \m1, \m1, 7            # leading one at bit 30, 7 bits below the last kept one
    slli \m2, \m2, 7
    li t4, 31
    bltu t3, t4, 94f
    li \m2, 1                   # shifted out entirely: only the sticky bit is left
    j 95f
94: srl t4, \m2, t3
    sll t5, t4, t3
    sltu t5, t5, \m2            # 1 when bits were shifted out
    or \m2, t4, t5              # sticky bit at bit 0
95: bne \s1, \s2, 96f
    add \m1, \m1, \m2           # < 2^32
    bgez \m1, 97f
    andi t4, \m1, 1             # leading one at bit 31: one bit right, keeping the sticky bit
    srli \m1, \m1, 1
    or \m1, \m1, t4
    addi \e1, \e1, 1
    j 97f
96: sub \m1, \m1, \m2           # >= 0
    beqz \m1, 98f               # x - x = +0
99: slli t4, \m1, 1             # leading one to bit 30, one bit at a time
    bltz t4, 97f
    mv \m1, t4
    addi \e1, \e1, -1
    j 99b
97: andi t4, \m1, 0x7f          # round bit (6) and sticky bits
    srli \m1, \m1, 7            # 24 bits
    andi t5, \m1, 1
    add t4, t4, t5              # above 0x40: round up
    addi t4, t4, 0x3f
    srli t4, t4, 7
    add \m1, \m1, t4
    srli t4, \m1, 24            # rounded up to 2^24
    srl \m1, \m1, t4
    add \e1, \e1, t4
    addi t4, \e1, -1
    bgtu t4, t6, .Lslow         # subnormal or overflowing sum
    j 90f
98: li \s1, 0
    li \e1, 0
    j 90f
91: bnez \e1, 90f               # x + 0 = x
    and \s1, \s1, \s2           # 0 + 0: -0 only when both are -0
    j 90f
92: mv \s1, \s2                 # 0 + y = y
    mv \e1, \e2
    mv \m1, \m2
90:
.endm

picomis_dot3:
    li t6, 253
    PRODUCT a0, a3, t0          # ax bx: sign a0, exponent a3, significand t0
    PRODUCT a1, a4, t1          # ay by
    PRODUCT a2, a5, t2          # az bz
    ADD a0, a3, t0, a1, a4, t1
    ADD a0, a3, t0, a2, a5, t2
    beqz a3, 1f                 # a signed zero
    addi a3, a3, -1
    slli a3, a3, 23
    add a3, a3, t0              # the leading one adds the last 1 to the exponent
    or a0, a0, a3
1:  li a1, 1
    ret
.Lslow:
    li a1, 0
    ret
    .size picomis_dot3, . - picomis_dot3
    .option pop
