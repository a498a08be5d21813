#!/usr/bin/env python3
"""Instruction profile of the firmware under QEMU (Debian's QEMU has no TCG plugins, so this
reads QEMU's execution log instead).

    cd firmware && PICOMIS_WIDTH=8 PICOMIS_HEIGHT=6 cargo build --release [--target thumbv6m-none-eabi]
    qemu-system-arm -machine netduinoplus2 -nographic -monitor none -serial null \
        -semihosting-config enable=on,target=native -icount shift=0 \
        -d in_asm,exec,nochain -D qemu.log -kernel ELF
    scripts/firmware-profile.py qemu.log ELF [TOP] [--charge FILE,FILE...]

Prints executed instructions per innermost (inlined) function, per outermost function and per
source line (addr2line -i), per symbol with its calls and instructions per call (from the symbol
table: right for assembly routines too, which have no line information), then the call sites of
out-of-line functions, then each innermost function and source file with the library routines it
calls charged to it (what a kernel function costs on a core without an FPU), then each function
inclusive of what is inlined into it. With `--charge
shape.rs,accel.rs,scene.rs`, also the instructions spent in those source files anywhere on the
inline chain, with the library routines they call (soft float, libm, memcpy) charged to them:
e.g. the ray queries' share (the firmware renders the film twice, once for the framebuffer and
once for the HDR digest: divide by twice its pixels for a figure per camera sample). Keep the
film tiny: the log holds one line per executed translation block. Needs arm-none-eabi-addr2line
and -nm for Arm builds, llvm-addr2line and llvm-nm for RISC-V ones (qemu-system-riscv32 -machine
sifive_e, same flags).
"""
import bisect
import collections
import re
import subprocess
import sys

INS = re.compile(r'^0x([0-9a-f]+):')
TRACE = re.compile(r'^Trace \d+: \S+ \[[0-9a-f]+/([0-9a-f]+)/')
# Out-of-line library routines, whose instructions `--charge` gives to the code that called them.
LIBRARY = re.compile(r'compiler_builtins|__aeabi_|__(add|sub|mul|div)sf3|__clzsi2|libm::|sqrtf|mem(cpy|set|move|clr)')


def short(s):
    for _ in range(3):
        s = re.sub(r'<[^<>]*>', '', s)
    return s[:90]


def binutils(elf):
    """The prefix of the nm and addr2line that read this ELF: GNU Arm's, or LLVM's for RISC-V."""
    with open(elf, 'rb') as f:
        header = f.read(20)
    return 'llvm-' if header[18:20] == b'\xf3\x00' else 'arm-none-eabi-'


def main():
    args = sys.argv[1:]
    charge = []
    if '--charge' in args:
        k = args.index('--charge')
        charge = args[k + 1].split(',')
        del args[k:k + 2]
    log, elf = args[0], args[1]
    top = int(args[2]) if len(args) > 2 else 30
    syms, ranges = {}, []
    tools = binutils(elf)
    nm = subprocess.run([tools + 'nm', '-C', '-S', '--defined-only', elf], capture_output=True, text=True)
    for line in nm.stdout.splitlines():
        p = line.split(' ', 3)
        # (llvm-nm also lists the assembler's local labels, .L*, which are not functions)
        if len(p) == 4 and p[2] in 'tTwW' and not p[3].startswith('.L'):
            start = int(p[0], 16) & ~1
            syms[start] = p[3]
            ranges.append((start, start + int(p[1], 16), p[3]))
    ranges.sort()
    starts = [r[0] for r in ranges]

    def symbol(a):
        i = bisect.bisect_right(starts, a) - 1
        return ranges[i][2] if i >= 0 and a < ranges[i][1] else '?'

    tb, cur, prev_last, site = {}, None, None, None
    counts, calls, charged, library = collections.Counter(), collections.Counter(), collections.Counter(), {}
    with open(log, errors='replace') as f:
        for line in f:
            if line.startswith('IN:'):
                cur = []
                continue
            m = INS.match(line)
            if m and cur is not None:
                cur.append(int(m.group(1), 16))
                continue
            if cur is not None and (line.strip() == '' or line.startswith('---')):
                if cur:
                    tb[cur[0]] = cur
                cur = None
            m = TRACE.match(line)
            if m:
                pc = int(m.group(1), 16)
                block = tb.get(pc, [pc])
                for a in block:
                    counts[a] += 1
                if pc in syms and prev_last is not None:
                    calls[(syms[pc], prev_last)] += 1
                prev_last = block[-1]
                if pc not in library:
                    library[pc] = bool(LIBRARY.search(symbol(pc)))
                if library[pc]:
                    charged[site] += len(block)
                else:
                    site = block[-1]
    pcs = sorted(set(counts) | {a for (_, a) in calls})
    out = subprocess.run([tools + 'addr2line', '-a', '-f', '-i', '-C', '-e', elf] + [hex(p) for p in pcs],
                         capture_output=True, text=True).stdout.splitlines()
    chains, i = {}, 0
    while i < len(out):
        addr = int(out[i], 16)
        i += 1
        chain = []
        while i < len(out) and not out[i].startswith('0x'):
            chain.append((short(out[i]), out[i + 1].split('/')[-1]))
            i += 2
        chains[addr] = chain or [('?', '?')]
    inner, outer, lines = collections.Counter(), collections.Counter(), collections.Counter()
    for a, n in counts.items():
        c = chains[a]
        inner[c[0][0]] += n
        outer[c[-1][0]] += n
        lines[c[0][0] + ' @ ' + c[0][1]] += n
    total = sum(counts.values())
    print(f'total instructions {total}')

    def show(title, c):
        print(f'\n== {title}')
        for k, v in c.most_common(top):
            print(f'{v:12d} {100 * v / total:5.1f}%  {k}')

    for title, c in (('innermost (inlined) function', inner), ('outermost function', outer), ('source line', lines)):
        show(title, c)
    per_symbol, entered = collections.Counter(), collections.Counter()
    for a, n in counts.items():
        per_symbol[symbol(a)] += n
    for (s, _), n in calls.items():
        entered[s] += n
    print('\n== symbol (symbol table): instructions, calls, instructions per call')
    for k, v in per_symbol.most_common(top):
        n = entered.get(k, 0)
        print(f'{v:12d} {100 * v / total:5.1f}%  {n:9d} calls {v / max(n, 1):8.1f}  {short(k)}')
    print('\n== calls into out-of-line functions: callee <- call site (innermost function, line)')
    agg = collections.Counter()
    for (s, a), n in calls.items():
        f, loc = chains[a][0]
        agg[(short(s)[:50], f[:60] + ' ' + loc)] += n
    for (s, w), n in agg.most_common(top):
        print(f'{n:10d}  {s:50s} <- {w}')
    by_fn, by_file = collections.Counter(), collections.Counter()
    own = [(a, n) for a, n in counts.items() if not LIBRARY.search(symbol(a))]
    for a, n in own + [(a, n) for a, n in charged.items() if a is not None]:
        f, loc = chains.get(a, [('?', '?')])[0]
        by_fn[f] += n
        by_file[loc.split(':')[0]] += n
    show('innermost function, with the library routines it calls charged to it', by_fn)
    show('source file, with the library routines it calls charged to it', by_file)
    inclusive = collections.Counter()
    for a, n in own + [(a, n) for a, n in charged.items() if a is not None]:
        for f in {f for f, _ in chains.get(a, [('?', '?')])}:
            inclusive[f] += n
    show('function anywhere on the inline chain (inclusive: the code inlined into it and the library '
         'routines it calls)', inclusive)
    if charge:
        def through(a):
            return any(loc.split(':')[0] in charge for _, loc in chains.get(a, []))
        own = sum(n for a, n in counts.items() if not library.get(a, False) and through(a))
        lib = sum(n for a, n in charged.items() if a is not None and through(a))
        print(f'\n== instructions through {", ".join(charge)} (library routines charged to their callers)')
        print(f'{own + lib:12d} {100 * (own + lib) / total:5.1f}%  ({own} in the code itself, {lib} in the routines it calls)')


if __name__ == '__main__':
    main()
