@ picomis: single-precision soft float for ARMv6-M (Thumb-1), see lib.rs.
@ AAPCS: operands in r0, r1, result in r0; r0-r3, r12 and the flags may be clobbered.
@ Round to nearest, ties to even. Fast paths for normal operands with a normal result; the rest
@ goes, with the original operands, to picomis_fadd_slow / picomis_fmul_slow / picomis_fdiv_slow
@ (slow.rs: compiler-builtins' bits).

    .syntax unified
    .thumb

@ ---------------------------------------------------------------------------------------------
@ Packs and rounds a result, then falls through to the caller's epilogue \done.
@ In: r0 bit 31 = sign, r2 = significand with its leading one at bit 31 (24 bits kept, bits
@ 7..0 below the last kept bit), r5 = e - 1 with e the result's biased exponent, checked by the
@ caller to be in 1..=254, \extra (optional) = more sticky bits in its low 16 bits, nonzero
@ when anything below r2 is nonzero (clobbered).
@ rd = (biased exponent of the float in rs) - 1, in 0..=253 for a normal float; branches to
@ `other` for zero, subnormals, infinities and NaNs (exponent 0 or 255: rd - 1 wraps or is 254).
    .macro exponent_m1 rd, rs, other
    lsls \rd, \rs, #1
    exponent_m1_of_shifted \rd, \other
    .endm

@ The same with rd = |x| << 1 already.
    .macro exponent_m1_of_shifted rd, other
    lsrs \rd, \rd, #24
    subs \rd, \rd, #1
    cmp \rd, #253
    bhi \other
    .endm

@ Restores the original operands, the saved registers and the return address, then jumps to
@ the library routine whose address is the word at `literal`: it returns to our caller.
    .macro tail_call_library literal
    pop {r0, r1, r4, r5, r6, r7}
    pop {r2}
    mov lr, r2
    ldr r2, \literal
    bx r2
    .endm

    .macro pack_round done, extra
    lsls r4, r5, #23            @ (e - 1) << 23: the leading one adds the last 1
    lsrs r1, r2, #8             @ 1.f, 24 bits
    adds r1, r1, r4
    lsrs r0, r0, #31
    lsls r0, r0, #31
    adds r0, r0, r1             @ sign | exponent | fraction, truncated
    lsls r1, r2, #25            @ C = round bit, r1 = the bits below it
    bcc \done                   @ below half an ulp: truncated is right
    .ifnb \extra
    lsls \extra, \extra, #16
    orrs r1, r1, \extra
    .endif
    bne 8f                      @ above half an ulp: round up
    adds r0, r0, #1             @ exactly half: round to even (up, then clear bit 0)
    lsrs r0, r0, #1
    lsls r0, r0, #1
    b \done
8:  adds r0, r0, #1             @ a carry into the exponent is right, up to infinity
    .endm

@ ---------------------------------------------------------------------------------------------
@ float __aeabi_fsub(float a, float b) = a + (-b)
    .section .text.picomis_fadd,"ax",%progbits
    .balign 4
    .global __aeabi_fsub
    .type __aeabi_fsub, %function
    .thumb_func
__aeabi_fsub:
    movs r2, #1
    lsls r2, r2, #31
    eors r1, r1, r2
    @ falls through into __aeabi_fadd

@ float __aeabi_fadd(float a, float b)
    .global __aeabi_fadd
    .type __aeabi_fadd, %function
    .thumb_func
__aeabi_fadd:
    lsls r2, r0, #1             @ X = |a| << 1
    beq .Lfadd_azero
    lsls r3, r1, #1             @ Y = |b| << 1
    beq .Lfadd_bzero
    push {r0, r1, r4, r5, r6, r7, lr}
    movs r6, r0
    eors r6, r6, r1             @ bit 31: the signs differ (magnitudes subtract)
    cmp r2, r3
    blo .Lfadd_swapped
    lsrs r4, r2, #24            @ ex, exponent of the larger
    cmp r4, #255
    beq .Lfadd_lib              @ infinity or NaN
    lsrs r5, r3, #24            @ ey
    beq .Lfadd_lib              @ the smaller is subnormal (zeros were handled before)
    subs r5, r4, r5             @ d = ex - ey >= 0
    movs r7, #1
    lsls r7, r7, #30
    lsls r2, r2, #8
    lsrs r2, r2, #2
    orrs r2, r2, r7             @ mx = 1.f at bits 30..7
    lsls r3, r3, #8
    lsrs r3, r3, #2
    orrs r3, r3, r7             @ my
.Lfadd_aligned:
    cmp r5, #8
    bhs .Lfadd_far
    lsrs r3, r3, r5             @ d < 8: my's low 7 bits are zero, nothing is shifted out
3:  cmp r6, #0
    blt .Lfadd_sub
    adds r2, r2, r3             @ < 2^32
    bmi 4f
    lsls r2, r2, #1             @ leading one at 30 -> 31, exponent ex
    b .Lfadd_round
4:  adds r4, r4, #1             @ leading one at 31: exponent ex + 1
    b .Lfadd_round
.Lfadd_sub:
    subs r2, r2, r3             @ >= 0, since |x| >= |y|
    beq .Lfadd_zero
    lsls r2, r2, #1
    bmi .Lfadd_round            @ leading one was at 30: exponent ex
5:  subs r4, r4, #1             @ cancellation: normalize one bit at a time
    lsls r2, r2, #1
    bpl 5b
.Lfadd_round:
    subs r5, r4, #1
    cmp r5, #253
    bhi .Lfadd_lib              @ subnormal or overflowing result
    pack_round .Lfadd_done
.Lfadd_done:
    add sp, #8
    pop {r4, r5, r6, r7, pc}
.Lfadd_zero:
    movs r0, #0                 @ x - x = +0
    b .Lfadd_done
.Lfadd_swapped:
    @ |b| > |a|: the same unpacking with the roles exchanged (r1, saved on the stack, is free).
    movs r0, r1                 @ r0: the operand of larger magnitude, which gives the sign
    lsrs r4, r3, #24            @ ex
    cmp r4, #255
    beq .Lfadd_lib
    lsrs r5, r2, #24            @ ey
    beq .Lfadd_lib
    subs r5, r4, r5
    movs r7, #1
    lsls r7, r7, #30
    lsls r1, r3, #8
    lsls r3, r2, #8
    lsrs r2, r1, #2
    lsrs r3, r3, #2
    orrs r2, r2, r7             @ mx
    orrs r3, r3, r7             @ my
    b .Lfadd_aligned
.Lfadd_far:
    cmp r5, #31
    bls 2f
    movs r5, #31                @ my >> 31 = 0: only the sticky bit is left
2:  movs r1, r3
    lsrs r3, r3, r5             @ my >> d
    movs r7, r3
    lsls r7, r7, r5
    cmp r7, r1
    beq 3b
    movs r7, #1
    orrs r3, r3, r7             @ bits shifted out: sticky bit at bit 0
    b 3b
.Lfadd_bzero:
    movs r3, #255
    lsls r3, r3, #24            @ 0xff000000: |x| << 1 of infinity
    cmp r2, r3
    bhi .Lfadd_lib0             @ NaN + 0: the library (it quiets the NaN)
    bx lr                       @ a + 0 = a (a nonzero: subnormal, normal or infinite)
.Lfadd_azero:
    lsls r3, r1, #1
    beq 1f
    movs r2, #255
    lsls r2, r2, #24
    cmp r3, r2
    bhi .Lfadd_lib0             @ 0 + NaN
    movs r0, r1                 @ 0 + b = b (b nonzero)
    bx lr
1:  ands r0, r0, r1             @ 0 + 0: -0 only when both are -0
    bx lr
.Lfadd_lib0:
    ldr r2, 9f                  @ no frame yet: r0, r1 and lr are the caller's
    bx r2
.Lfadd_lib:
    tail_call_library 9f
    .balign 4
9:  .word picomis_fadd_slow
    .size __aeabi_fadd, . - __aeabi_fadd
    .size __aeabi_fsub, . - __aeabi_fsub

@ ---------------------------------------------------------------------------------------------
@ float __aeabi_fmul(float a, float b)
    .section .text.picomis_fmul,"ax",%progbits
    .balign 4
    .global __aeabi_fmul
    .type __aeabi_fmul, %function
    .thumb_func
__aeabi_fmul:
    lsls r2, r0, #1
    beq .Lfmul_azero
    lsls r3, r1, #1
    beq .Lfmul_bzero
    push {r0, r1, r4, r5, r6, r7, lr}
    exponent_m1_of_shifted r2, .Lfmul_lib   @ ea - 1 (a subnormal, infinite or NaN: the library)
    exponent_m1_of_shifted r3, .Lfmul_lib   @ eb - 1
    adds r4, r2, r3
    subs r4, r4, #124           @ e = ea + eb - 126, for a product of significands in [2, 4)
    @ 1.fa = ah * 2^16 + al, 1.fb = bh * 2^16 + bl (ah, bh: 8 bits; al, bl: 16 bits)
    lsls r2, r0, #9
    lsrs r2, r2, #25
    adds r2, r2, #128           @ ah
    uxth r5, r0                 @ al
    lsls r6, r1, #9
    lsrs r6, r6, #25
    adds r6, r6, #128           @ bh
    uxth r7, r1                 @ bl
    eors r0, r0, r1             @ sign of the result in bit 31
    movs r1, r2
    muls r1, r7, r1             @ ah * bl
    muls r7, r5, r7             @ al * bl
    muls r5, r6, r5             @ al * bh
    muls r6, r2, r6             @ ah * bh
    @ floor(P / 2^16) = ah bh 2^16 + ah bl + al bh + floor(al bl / 2^16) < 2^32 (P < 2^48): no
    @ partial sum overflows; the low 16 bits of al bl are the sticky bits.
    lsls r6, r6, #16
    adds r6, r6, r1
    adds r6, r6, r5
    lsrs r2, r7, #16
    adds r2, r2, r6             @ product >> 16: leading one at bit 31 or 30
    bmi 1f
    lsls r2, r2, #1             @ product in [1, 2): one binade lower
    subs r4, r4, #1
1:  subs r5, r4, #1             @ (the sticky bits: the low 16 bits of r7)
    cmp r5, #253
    bhi .Lfmul_lib              @ subnormal or overflowing result
    pack_round .Lfmul_done, r7
.Lfmul_done:
    add sp, #8
    pop {r4, r5, r6, r7, pc}
.Lfmul_azero:
    lsls r2, r1, #1             @ a = 0: r2 = |b| << 1 (b may be zero too)
.Lfmul_bzero:
    @ one operand is a zero, r2 = |the other| << 1, nonzero or zero. 0 * finite = signed 0.
    movs r3, #255
    lsls r3, r3, #24            @ 0xff000000: |x| << 1 of infinity
    cmp r2, r3
    bhs .Lfmul_lib0             @ 0 * inf, 0 * NaN: the library (NaN)
    eors r0, r0, r1
    lsrs r0, r0, #31
    lsls r0, r0, #31
    bx lr
.Lfmul_lib0:
    ldr r2, 9f                  @ no frame yet: r0, r1 and lr are the caller's
    bx r2
.Lfmul_lib:
    tail_call_library 9f
    .balign 4
9:  .word picomis_fmul_slow
    .size __aeabi_fmul, . - __aeabi_fmul

@ ---------------------------------------------------------------------------------------------
@ float __aeabi_fdiv(float a, float b)
@ With A = 1.fa and B = 1.fb as 24-bit integers (A doubled when A < B, so that A / B is in
@ [1, 2)), the result's significand comes from Q' = floor(A 2^24 / B), 25 bits. A quotient of
@ 24-bit significands never lies exactly halfway between two 24-bit values (A 2^24 has 24 or more
@ factors of two, B at most 23), so rounding to nearest is (Q' + 1) >> 1 and no sticky bit is
@ needed. Q' is built from a 16-bit reciprocal X <= 2^39 / B (a 128-entry table, one Newton
@ step) in two digit steps, q1 (15 bits) and q2 (about 10 more), each from a remainder that is
@ exact because its true value is small (computed mod 2^32 with MULS), then made exact by one
@ correction from the final remainder. The bounds in the comments are proved for every B (and
@ so every A) by tools/tests/fdiv_bound.rs (a host test); firmware/src/fpcheck.rs checks
@ the routine against compiler-builtins' __divsf3 bit for bit.
    .section .text.picomis_fdiv,"ax",%progbits
    .balign 4
    .global __aeabi_fdiv
    .type __aeabi_fdiv, %function
    .thumb_func
__aeabi_fdiv:
    push {r0, r1, r4, r5, r6, r7, lr}
    exponent_m1 r3, r1, .Lfdiv_lib      @ eb - 1 (b zero, subnormal, infinite or NaN: the library)
    exponent_m1 r2, r0, .Lfdiv_aspecial @ ea - 1
    subs r4, r2, r3             @ ea - eb
    movs r5, #1
    lsls r5, r5, #23            @ 2^23, the implicit one
    lsls r2, r0, #9
    lsrs r2, r2, #9
    orrs r2, r2, r5             @ A = 1.fa
    lsls r3, r1, #9
    lsrs r3, r3, #9
    orrs r3, r3, r5             @ B = 1.fb, in [2^23, 2^24)
    eors r0, r0, r1             @ sign of the result in bit 31
    cmp r2, r3
    bhs 1f
    lsls r2, r2, #1             @ A < B: 2A, in (B, 2B), and the exponent one lower
    subs r4, r4, #1
1:  adds r4, r4, #126           @ e - 1, e = ea - eb + 127 the result's biased exponent
    cmp r4, #253
    bhi .Lfdiv_lib              @ subnormal or overflowing result
    @ X0 = 2^24 / (257 + 2i) for B in [2^23 + 2^16 i, 2^23 + 2^16 (i + 1)): 1 / the middle of
    @ the interval, within 1/257 of 2^31 / b16 below, with b16 = (B >> 8) + 1 >= B / 2^8.
    ldr r7, .Lfdiv_tab
    lsrs r6, r3, #16            @ 128 + i
    lsls r6, r6, #1
    ldrh r6, [r7, r6]           @ X0
    lsrs r7, r3, #8
    adds r7, r7, #1             @ b16, in (2^15, 2^16]
    muls r7, r6, r7             @ P = X0 b16 < 2^32, within 2^31 / 257 of 2^31
    lsls r1, r5, #8             @ 2^31
    subs r7, r1, r7             @ E = 2^31 - P, |E| < 2^23
    asrs r7, r7, #8
    muls r7, r6, r7             @ X0 floor(E / 2^8), |.| < 2^31
    asrs r7, r7, #23
    adds r6, r6, r7             @ X = X0 (1 + E / 2^31), rounded down: X <= 2^31 / b16 <= 2^39 / B
    @ q1 = floor((A >> 9) X / 2^16) <= A 2^14 / B
    lsrs r7, r2, #9             @ A >> 9 < 2^16 (A < 2^25)
    muls r7, r6, r7             @ < 2^32 (X <= 2^16)
    lsrs r7, r7, #16            @ q1 < 2^15
    lsls r1, r2, #14
    movs r5, r7
    muls r5, r3, r5
    subs r1, r1, r5             @ r1 = A 2^14 - q1 B, in [0, 2^26): exact mod 2^32
    @ q2 = floor((r1 >> 11) X / 2^18) <= r1 2^10 / B, at most 1 below
    lsrs r5, r1, #11            @ < 2^16 (r1 < 2^27)
    muls r5, r6, r5
    lsrs r5, r5, #18            @ q2
    lsls r7, r7, #10
    adds r7, r7, r5             @ Q = q1 2^10 + q2 <= Q'
    muls r5, r3, r5
    lsls r1, r1, #10
    subs r1, r1, r5             @ R = A 2^24 - Q B, in [0, 2B): exact mod 2^32
    cmp r1, r3                  @ C = (R >= B): Q' = Q + C
    movs r5, #1                 @ (MOVS leaves C alone)
    adcs r7, r7, r5             @ Q' + 1, Q' in [2^24, 2^25): round to nearest, no ties
    lsrs r7, r7, #1             @ 1.f in [2^23, 2^24]: 2^24 carries into the exponent, up to infinity
    lsls r4, r4, #23
    adds r7, r7, r4
    lsrs r0, r0, #31
    lsls r0, r0, #31
    adds r0, r0, r7
.Lfdiv_done:
    add sp, #8
    pop {r4, r5, r6, r7, pc}
.Lfdiv_aspecial:
    lsls r2, r0, #1
    bne .Lfdiv_lib              @ a subnormal, infinite or NaN
    eors r0, r0, r1             @ 0 / normal = signed 0
    lsrs r0, r0, #31
    lsls r0, r0, #31
    b .Lfdiv_done
.Lfdiv_lib:
    tail_call_library 9f
    .balign 4
.Lfdiv_tab:
    .word .Lfdiv_recip - 256    @ indexed by (B >> 16) in [128, 256), two bytes an entry
9:  .word picomis_fdiv_slow
.Lfdiv_recip:
    FDIV_RECIPROCALS
    .size __aeabi_fdiv, . - __aeabi_fdiv

@ ---------------------------------------------------------------------------------------------
@ int __aeabi_fcmp{eq,lt,le,gt,ge}(float a, float b): 1 if the relation holds, else 0; 0 when
@ either is NaN. Keys k(x) = x ^ ((x asr 31) lsr 1) order the floats as signed integers, except
@ that k(-0) = -1 < k(+0) = 0 and NaNs fall outside [k(-inf), k(+inf)]: both are checked only
@ on the path where they can change the answer.

    .macro fbegin name
    .section .text.picomis_\name,"ax",%progbits
    .balign 2
    .global \name
    .type \name, %function
    .thumb_func
\name:
    .endm

@ r2 = k(r0), r3 = k(r1)
    .macro fkeys
    asrs r2, r0, #31
    lsrs r2, r2, #1
    eors r2, r2, r0
    asrs r3, r1, #31
    lsrs r3, r3, #1
    eors r3, r3, r1
    .endm

@ Branches to \nan if r0 or r1 is a NaN (clobbers r2, r3).
    .macro fnan nan
    movs r2, #255
    lsls r2, r2, #24
    lsls r3, r0, #1
    cmp r3, r2
    bhi \nan
    lsls r3, r1, #1
    cmp r3, r2
    bhi \nan
    .endm

@ Branches to \zero if r0 and r1 are both zeros (clobbers r2).
    .macro fzeros zero
    movs r2, r0
    orrs r2, r2, r1
    lsls r2, r2, #1
    beq \zero
    .endm

@ Both operands with the sign bit clear (+0 up to +inf and positive NaNs, the common case),
@ x < y (\strict) or x <= y: the bit patterns order them as unsigned integers, and when x <= y
@ is true a NaN among them must be y. Branches to \slow when a sign bit is set, to \no when
@ the relation is false; falls through when it holds.
    .macro fpositive x, y, strict, slow, no
    movs r2, r0
    orrs r2, r2, r1
    bmi \slow
    cmp \x, \y
    .ifnb \strict
    bhs \no
    .else
    bhi \no
    .endif
    movs r2, #255
    lsls r2, r2, #23            @ 0x7f800000, +inf
    cmp \y, r2
    bhi \no                     @ y (and maybe x) is a NaN
    .endm

@ a < b (\swap: b < a, for gt)
    .macro flt name, a, b, x, y
    fbegin \name
    fpositive \x, \y, strict, 5f, 0f
    movs r0, #1
    bx lr
5:  fkeys
    cmp \a, \b
    blt 1f
0:  movs r0, #0
    bx lr
1:  fnan 0b
    fzeros 0b
    movs r0, #1
    bx lr
    .size \name, . - \name
    .endm

@ a <= b (\swap: b <= a, for ge)
    .macro fle name, a, b, x, y
    fbegin \name
    fpositive \x, \y, , 5f, 0f
    movs r0, #1
    bx lr
5:  fkeys
    cmp \a, \b
    ble 1f
    fzeros 2f                   @ k says >, but +0 <= -0
0:  movs r0, #0
    bx lr
1:  fnan 0b
2:  movs r0, #1
    bx lr
    .size \name, . - \name
    .endm

    flt __aeabi_fcmplt, r2, r3, r0, r1
    flt __aeabi_fcmpgt, r3, r2, r1, r0
    fle __aeabi_fcmple, r2, r3, r0, r1
    fle __aeabi_fcmpge, r3, r2, r1, r0

@ a == b: the same bits and not a NaN, or two zeros.
    fbegin __aeabi_fcmpeq
    cmp r0, r1
    bne 2f
    movs r2, #255
    lsls r2, r2, #24
    lsls r3, r0, #1
    cmp r3, r2
    bhi 0f
1:  movs r0, #1
    bx lr
2:  fzeros 1b
0:  movs r0, #0
    bx lr
    .size __aeabi_fcmpeq, . - __aeabi_fcmpeq

@ ---------------------------------------------------------------------------------------------
@ long long __aeabi_lmul(long long a, long long b): the low 64 bits of a * b (a in r1:r0, b in
@ r3:r2). (al*bl) from four 16x16-bit products, plus (ah*bl + al*bh) << 32.
    fbegin __aeabi_lmul
    push {r4, r5, r6, lr}
    muls r1, r2, r1             @ ah * bl (low 32 bits)
    muls r3, r0, r3             @ al * bh
    adds r3, r3, r1             @ cross terms, mod 2^32
    lsrs r4, r0, #16            @ a1
    uxth r0, r0                 @ a0
    lsrs r5, r2, #16            @ b1
    uxth r2, r2                 @ b0
    movs r6, r0
    muls r6, r5, r6             @ a0 * b1
    muls r0, r2, r0             @ a0 * b0
    muls r2, r4, r2             @ a1 * b0
    muls r4, r5, r4             @ a1 * b1
    lsls r5, r6, #16
    lsrs r6, r6, #16
    adds r0, r0, r5
    adcs r4, r4, r6
    lsls r5, r2, #16
    lsrs r2, r2, #16
    adds r0, r0, r5
    adcs r4, r4, r2
    adds r1, r4, r3
    pop {r4, r5, r6, pc}
    .size __aeabi_lmul, . - __aeabi_lmul

@ ---------------------------------------------------------------------------------------------
@ Shifts \x (non-zero) left until its leading one is at bit 31, in steps of 16, 8, 4, 2 and 1
@ (no CLZ on ARMv6-M), stepping \n by each shift with \op (`subs`: an exponent; `adds`: a
@ count). Clobbers r2.
    .macro leading_one_to_31 x, n, op
    lsrs r2, \x, #16
    bne 1f
    lsls \x, \x, #16
    \op \n, \n, #16
1:  lsrs r2, \x, #24
    bne 2f
    lsls \x, \x, #8
    \op \n, \n, #8
2:  lsrs r2, \x, #28
    bne 3f
    lsls \x, \x, #4
    \op \n, \n, #4
3:  lsrs r2, \x, #30
    bne 4f
    lsls \x, \x, #2
    \op \n, \n, #2
4:  cmp \x, #0
    blt 5f
    lsls \x, \x, #1
    \op \n, \n, #1
5:
    .endm

@ ---------------------------------------------------------------------------------------------
@ float __aeabi_ui2f(unsigned a): rounded to nearest, ties to even. The leading one is moved to
@ bit 31 (leading_one_to_31), then packed like the other routines.
    fbegin __aeabi_ui2f
    cmp r0, #0
    beq 9f                      @ 0 -> +0
    movs r1, #157               @ e - 1 for a leading one at bit 31 (e = 127 + 31)
    leading_one_to_31 r0, r1, subs
    lsrs r3, r0, #8             @ 1.f, 24 bits
    lsls r1, r1, #23
    adds r3, r3, r1             @ exponent | fraction, truncated
    lsls r2, r0, #25            @ C = round bit, r2 = the bits below it
    bcc 7f
    bne 6f
    adds r3, r3, #1             @ exactly half: round to even
    lsrs r3, r3, #1
    lsls r3, r3, #1
    b 7f
6:  adds r3, r3, #1
7:  movs r0, r3
9:  bx lr
    .size __aeabi_ui2f, . - __aeabi_ui2f

@ ---------------------------------------------------------------------------------------------
@ int __clzsi2(unsigned a): the leading zeros of a (32 for 0), the shifts of leading_one_to_31
@ (compiler-builtins' takes about 35 instructions). The sampler's numbers in [0, 1)
@ get their exponent from it (rng.rs, `unit_from_bits`).
    fbegin __clzsi2
    movs r1, #32
    cmp r0, #0
    beq 9f
    movs r1, #0
    leading_one_to_31 r0, r1, adds
9:  movs r0, r1
    bx lr
    .size __clzsi2, . - __clzsi2
