# picomis: memcpy for RV32 (see riscv.rs). build.rs links with --wrap=memcpy: the compiler's
# copies of structs (a shading point's frame, nine words, and the like) reach __wrap_memcpy, and
# everything else is copied a byte at a time here (compiler-builtins' memcpy, 392 bytes of code,
# is then not linked).

    .section .text.picomis_memcpy,"ax",@progbits
    .globl __wrap_memcpy
    .type __wrap_memcpy, @function
    .balign 2
# void *__wrap_memcpy(void *dst, const void *src, size_t n): returns dst.
__wrap_memcpy:
    or t0, a0, a1
    or t0, t0, a2
    andi t0, t0, 3
    bnez t0, 3f                 # a pointer or the size not a multiple of 4
    mv t1, a0
    add t2, a1, a2              # the end of the source
    beq a1, t2, 2f
1:  lw t0, 0(a1)
    addi a1, a1, 4
    sw t0, 0(t1)
    addi t1, t1, 4
    bne a1, t2, 1b
2:  ret
3:  mv t1, a0                   # a byte at a time (rare: the compiler's copies are of words)
    add t2, a1, a2
    beq a1, t2, 5f
4:  lbu t0, 0(a1)
    addi a1, a1, 1
    sb t0, 0(t1)
    addi t1, t1, 1
    bne a1, t2, 4b
5:  ret
    .size __wrap_memcpy, . - __wrap_memcpy
