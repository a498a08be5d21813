@ picomis: a signed 32 x 32 -> 64-bit multiply for ARMv6-M (Cortex-M0, Thumb-1), see fixed.rs.
@
@ i64 picomis_mul_wide(i32 a, i32 b): r1:r0 = a b, exact. With a = ah 2^16 + al and
@ b = bh 2^16 + bl (ah, bh signed: the arithmetic shifts; al, bl unsigned: the low halves),
@ a b = ah bh 2^32 + (ah bl + al bh) 2^16 + al bl: al bl fits 32 unsigned bits, the middle
@ products 32 signed bits each, and each is added shifted by 16 as a 64-bit value (low half by
@ ADDS, high half and carry by ADCS). Four MULS where compiler-builtins' __aeabi_lmul also
@ forms the cross terms of the sign-extended operands.

    .syntax unified
    .thumb
    .section .text.picomis_mul_wide,"ax",%progbits
    .global picomis_mul_wide
    .type picomis_mul_wide, %function
    .balign 2
    .thumb_func
picomis_mul_wide:
    push {r4}
    asrs r2, r0, #16            @ ah
    uxth r0, r0                 @ al
    asrs r3, r1, #16            @ bh
    uxth r1, r1                 @ bl
    movs r4, r0
    muls r4, r1, r4             @ al bl: the low word
    muls r1, r2, r1             @ ah bl
    muls r0, r3, r0             @ al bh
    muls r3, r2, r3             @ ah bh: the high word
    lsls r2, r1, #16
    asrs r1, r1, #16
    adds r4, r4, r2             @ + (ah bl) 2^16
    adcs r3, r1
    lsls r2, r0, #16
    asrs r0, r0, #16
    adds r4, r4, r2             @ + (al bh) 2^16
    adcs r3, r0
    movs r0, r4
    movs r1, r3
    pop {r4}
    bx lr
    .size picomis_mul_wide, . - picomis_mul_wide
