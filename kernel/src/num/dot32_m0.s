@ picomis: the 64-bit dot product of two 32-bit integer vectors for ARMv6-M (Cortex-M0,
@ Thumb-1), see fixed.rs (`dot32`) and int_m0.rs.
@
@ i64 picomis_dot32(const i32 a[3], const i32 b[3]): r1:r0 = a0 b0 + a1 b1 + a2 b2, each product
@ exact and the sum in 64 bits (wrapping, as the Rust sum is without overflow checks; the fixed-
@ point bounds keep it within range). Each product as in mul_wide_m0.s: with a = ah 2^16 + al,
@ b = bh 2^16 + bl (ah, bh signed, al, bl unsigned), a b = ah bh 2^32 + (ah bl + al bh) 2^16
@ + al bl, accumulated into the 64-bit sum hi:lo (r3:r2) by ADDS/ADCS. One call and no
@ intermediate 64-bit results moved between calls, where three calls of picomis_mul_wide and
@ the sums took about 95 instructions.

    .syntax unified
    .thumb
    .section .text.picomis_dot32,"ax",%progbits
    .global picomis_dot32
    .type picomis_dot32, %function
    .balign 2
    .thumb_func
picomis_dot32:
    push {r4, r5, r6, r7, lr}
    movs r2, #0                 @ lo
    movs r3, #0                 @ hi
    .irp o, 0, 4, 8
    ldr r4, [r0, #\o]           @ a_k
    ldr r5, [r1, #\o]           @ b_k
    asrs r6, r4, #16            @ ah
    asrs r7, r5, #16            @ bh
    uxth r4, r4                 @ al
    uxth r5, r5                 @ bl
    mov ip, r6                  @ ah, kept for ah bl
    muls r6, r7, r6             @ ah bh
    muls r7, r4, r7             @ al bh
    muls r4, r5, r4             @ al bl
    adds r2, r2, r4             @ lo += al bl (unsigned)
    adcs r3, r6                 @ hi += ah bh + carry
    mov r6, ip
    muls r5, r6, r5             @ ah bl
    lsls r4, r7, #16            @ + (al bh) 2^16 as 64 bits
    asrs r7, r7, #16
    adds r2, r2, r4
    adcs r3, r7
    lsls r4, r5, #16            @ + (ah bl) 2^16 as 64 bits
    asrs r5, r5, #16
    adds r2, r2, r4
    adcs r3, r5
    .endr
    movs r0, r2
    movs r1, r3
    pop {r4, r5, r6, r7, pc}
    .size picomis_dot32, . - picomis_dot32
