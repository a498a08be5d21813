# picomis: the register save and restore routines of RISC-V's -msave-restore (LLVM's
# `save-restore` target feature, which scripts/firmware.sh turns on for the size-optimised
# RV32IMC build): a function calls `jal t0, __riscv_save_N` instead of storing ra and s0..s(N-1)
# itself, and returns with `tail __riscv_restore_N` instead of loading them and `ret`. One copy
# of the stores and loads for the whole program instead of one in every function.
#
# The layout LLVM's frame lowering assumes (RISCVFrameLowering, spillSlotTable32): ra at the
# caller's sp - 4, s0 at - 8, ... s11 at - 52, in a frame of 4 (N + 1) bytes rounded up to 16.
# Each entry allocates 64 bytes, stores its group of four registers and the groups below it at
# their offsets from the top, and gives back the unused part (t1) at the end. t0 holds the return
# address; t1 is free at a function's entry (a temporary, not an argument).

    .section .text.picomis_riscv_save,"ax",@progbits
    .globl __riscv_save_12
    .globl __riscv_save_11, __riscv_save_10, __riscv_save_9, __riscv_save_8
    .globl __riscv_save_7, __riscv_save_6, __riscv_save_5, __riscv_save_4
    .globl __riscv_save_3, __riscv_save_2, __riscv_save_1, __riscv_save_0
    .balign 2
__riscv_save_12:
    addi sp, sp, -64
    li t1, 0
    sw s11, 12(sp)
    j 1f
__riscv_save_11:
__riscv_save_10:
__riscv_save_9:
__riscv_save_8:
    addi sp, sp, -64
    li t1, 16
1:  sw s10, 16(sp)
    sw s9, 20(sp)
    sw s8, 24(sp)
    sw s7, 28(sp)
    j 2f
__riscv_save_7:
__riscv_save_6:
__riscv_save_5:
__riscv_save_4:
    addi sp, sp, -64
    li t1, 32
2:  sw s6, 32(sp)
    sw s5, 36(sp)
    sw s4, 40(sp)
    sw s3, 44(sp)
    j 3f
__riscv_save_3:
__riscv_save_2:
__riscv_save_1:
__riscv_save_0:
    addi sp, sp, -64
    li t1, 48
3:  sw s2, 48(sp)
    sw s1, 52(sp)
    sw s0, 56(sp)
    sw ra, 60(sp)
    add sp, sp, t1
    jr t0

# Entered by a tail call with sp at the frame the matching save made; returns to ra.
    .section .text.picomis_riscv_restore,"ax",@progbits
    .globl __riscv_restore_12
    .globl __riscv_restore_11, __riscv_restore_10, __riscv_restore_9, __riscv_restore_8
    .globl __riscv_restore_7, __riscv_restore_6, __riscv_restore_5, __riscv_restore_4
    .globl __riscv_restore_3, __riscv_restore_2, __riscv_restore_1, __riscv_restore_0
    .balign 2
__riscv_restore_12:
    lw s11, 12(sp)
    addi sp, sp, 16
__riscv_restore_11:
__riscv_restore_10:
__riscv_restore_9:
__riscv_restore_8:
    lw s10, 0(sp)
    lw s9, 4(sp)
    lw s8, 8(sp)
    lw s7, 12(sp)
    addi sp, sp, 16
__riscv_restore_7:
__riscv_restore_6:
__riscv_restore_5:
__riscv_restore_4:
    lw s6, 0(sp)
    lw s5, 4(sp)
    lw s4, 8(sp)
    lw s3, 12(sp)
    addi sp, sp, 16
__riscv_restore_3:
__riscv_restore_2:
__riscv_restore_1:
__riscv_restore_0:
    lw s2, 0(sp)
    lw s1, 4(sp)
    lw s0, 8(sp)
    lw ra, 12(sp)
    addi sp, sp, 16
    ret
