"""Instructions a kernel runs, by the line of lsubdiv's source they come from.

callgrind counts instructions, repeatably, where this shared host's timings move 20-30 %
between batches. valgrind has no AVX-512, so the kernels run their AVX2 path under it.

    valgrind --tool=callgrind --dump-instr=yes --callgrind-out-file=cg.out \
        target/release/lsubdiv bench --mesh torus:256:256 --runs 1 [--f32]
    python3 bench/instructions.py cg.out target/release/lsubdiv run_avx2 \
        patch.rs,composed.rs,stream.rs 131072

Arguments: the callgrind file, the binary, a part of the function's name, the source files
to attribute to (each instruction goes to the innermost inlined frame in one of them, by
`addr2line -i`), and what to divide by (131,072: a warm-up and one timed run of the torus's
65,536 faces, so instructions a face).
"""
import collections
import glob
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent


def value(token, last):
    """A callgrind position: absolute, relative (+n, -n) or the same (*)."""
    if token.startswith('+'):
        return last + int(token[1:], 0)
    if token.startswith('-'):
        return last - int(token[1:], 0)
    if token == '*':
        return last
    return int(token, 0)


def self_costs(path, func):
    """Instructions at each address of the functions whose name contains `func` (self cost:
    the inclusive cost of a call, given after a `calls=` line, is left out)."""
    names, name, costs = {}, None, collections.Counter()
    addr = line = 0
    after_call = False
    for text in open(path):
        text = text.rstrip('\n')
        m = re.match(r'^(c?)fn=\((\d+)\)(?: (.*))?$', text)
        if m:
            if m.group(3):
                names[m.group(2)] = m.group(3)
            if not m.group(1):
                name = names.get(m.group(2))
            continue
        if text.startswith('calls='):
            after_call = True
            continue
        if not text or not (text[0].isdigit() or text[0] in '+-*'):
            continue
        tokens = text.split()
        if len(tokens) < 3:
            continue
        addr, line = value(tokens[0], addr), value(tokens[1], line)
        if after_call:
            after_call = False
        elif name and func in name:
            costs[addr] += int(tokens[2])
    return costs


def frames(binary, addrs):
    """Each address's inlined frames, innermost first (`addr2line -i`)."""
    out = subprocess.run(['addr2line', '-i', '-a', '-e', binary],
                         input='\n'.join(hex(a) for a in addrs),
                         capture_output=True, text=True, check=True).stdout
    chains, cur = {}, None
    for text in out.splitlines():
        if text.startswith('0x'):
            cur = int(text, 16)
            chains[cur] = []
        else:
            chains[cur].append(text.split(' ')[0])
    return chains


def source(place):
    """The text of `file.rs:line` in the runtime's sources, if found."""
    fname, _, line = place.partition(':')
    for found in glob.glob(str(ROOT / 'runtime/src/**' / fname), recursive=True):
        lines = open(found).read().splitlines()
        if line.isdigit() and int(line) <= len(lines):
            return lines[int(line) - 1].strip()[:80]
    return ''


def main():
    path, binary, func, files, per = sys.argv[1:6]
    files, per = files.split(','), float(per)
    costs = self_costs(path, func)
    chains = frames(binary, sorted(costs))
    by_place = collections.Counter()
    for addr, cost in costs.items():
        place = next((f.rsplit('/', 1)[-1] for f in chains.get(addr, [])
                      if any(f.split(':')[0].endswith(k) for k in files)), '?')
        by_place[place] += cost
    print(f'total {sum(costs.values())}: {sum(costs.values()) / per:.1f} a unit')
    for place, cost in by_place.most_common(45):
        print(f'{cost / per:8.1f} {place:22s} {source(place)}')


if __name__ == '__main__':
    main()
