#!/usr/bin/env bash
# The portable build's kernel objects (cmake/ArborKernelSets.cmake): each defines one global symbol
# of its own, its entry arbor_kernels_<set> (the sanitizers' __asan*/__sancov* excepted), so no
# inline function or template of one set can stand in for another's; the sse4 object uses no ymm
# or zmm register (no AVX) and the avx2 object no zmm (no AVX-512), while the avx512 object does
# use zmm (so that the disassembly check is seen to find what it looks for).
# Usage: kernel_objects_test.sh OBJDUMP NM DIR (DIR holds arbor_kernels_{sse4,avx2,avx512}.o)
set -u
OBJDUMP=$1 NM=$2 DIR=$3
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }

# count OBJECT REGEX: instructions of OBJECT whose operands match REGEX
count() { "$OBJDUMP" -d --no-show-raw-insn "$1" | grep -cE "$2"; }

for set in sse4 avx2 avx512; do
  obj=$DIR/arbor_kernels_$set.o
  [ -f "$obj" ] || { fail "$obj missing"; continue; }
  globals=$("$NM" -g --defined-only "$obj" | awk '{print $3}' | grep -vE '^(__asan|__sancov)')
  [ "$globals" = "arbor_kernels_$set" ] || fail "$set: global symbols other than its entry: $(echo $globals)"
  # STB_GNU_UNIQUE ('u'): merged across objects by the dynamic linker, whatever objcopy says
  unique=$("$NM" --defined-only "$obj" | awk '$2 == "u" {print $3}')
  [ -z "$unique" ] || fail "$set: unique symbols: $(echo $unique)"
done
n=$(count "$DIR/arbor_kernels_sse4.o" '%[yz]mm')
[ "$n" -eq 0 ] || fail "sse4: $n instructions on ymm/zmm registers, e.g. $("$OBJDUMP" -d --no-show-raw-insn "$DIR/arbor_kernels_sse4.o" | grep -m1 -E '%[yz]mm')"
n=$(count "$DIR/arbor_kernels_avx2.o" '%zmm')
[ "$n" -eq 0 ] || fail "avx2: $n instructions on zmm registers"
n=$(count "$DIR/arbor_kernels_avx512.o" '%zmm')
[ "$n" -gt 0 ] || fail "avx512: no instruction on a zmm register (is it compiled for AVX-512?)"
n=$(count "$DIR/arbor_kernels_avx2.o" '%ymm')
[ "$n" -gt 0 ] || fail "avx2: no instruction on a ymm register (is it compiled for AVX2?)"

[ $fails -eq 0 ] && echo "kernel objects: one entry each; sse4 without ymm/zmm, avx2 without zmm"
exit $((fails > 0))
