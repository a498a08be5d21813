# picomis: memcpy for RV32 (see riscv.rs). build.rs links with --wrap=memcpy: the compiler's
# copies of structs (a shading point's frame, nine words, and the like) reach __wrap_memcpy, and
# everything but word-aligned whole words goes on to compiler-builtins' memcpy (__real_memcpy).

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
3:  tail __real_memcpy
    .size __wrap_memcpy, . - __wrap_memcpy
