/* The division's reciprocal table, shared by m0.s and rv32.s: X0 = 2^24 / (257 + 2i) for
   i = 0..127, two bytes each, the 1 / the middle of divisor interval i
   (tools/tests/fdiv_bound.rs proves the division's error bound from these values). A macro,
   so that each routine places the table where its loads reach it. */
.macro FDIV_RECIPROCALS
    .set i, 0
    .rept 128
    .hword 16777216 / (257 + 2 * i)
    .set i, i + 1
    .endr
.endm

