@ picomis: the restoring division steps of fixed::div_floor for ARMv6-M (Cortex-M0, Thumb-1),
@ which has no divide instruction.
@
@ u32 picomis_div_steps(u32 rem, u32 w, u32 d): r0 = rem < d <= 2^31 (the dividend's bits from
@ 31 up), r1 = w (its bits 30..0, on top), r2 = d. Each of the 31 steps shifts the next
@ dividend bit out of w's top into the remainder and, by the same ADCS, the previous step's
@ quotient bit into w's bottom (the carry: CMP leaves it set exactly when rem >= d, and SUBS of
@ d from such a rem leaves it set too); a last ADCS brings in the last quotient bit. The
@ remainder stays below d, so twice it plus one fits 32 bits. Four instructions a step, five
@ where the quotient bit is one, where the compiler's loop took about ten.

    .syntax unified
    .thumb
    .section .text.picomis_div_steps,"ax",%progbits
    .global picomis_div_steps
    .type picomis_div_steps, %function
    .balign 2
    .thumb_func
picomis_div_steps:
    adds r3, r2, #0             @ clears the carry: no quotient bit before the first step
    .rept 31
    adcs r1, r1                 @ w = 2 w + the previous quotient bit; carry = the dividend bit
    adcs r0, r0                 @ rem = 2 rem + that bit
    cmp r0, r2
    bcc 1f                      @ rem < d: quotient bit 0 (carry clear)
    subs r0, r0, r2             @ quotient bit 1 (carry set)
1:
    .endr
    adcs r1, r1                 @ the last quotient bit
    movs r0, r1
    bx lr
    .size picomis_div_steps, . - picomis_div_steps
