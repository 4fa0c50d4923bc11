#!/usr/bin/env bash
# The FMUs' lifecycles under valgrind's memcheck: the randomized call-sequence test
# (tests/call_sequences.rs: the three FMU binaries, instantiate ... free in every order, FMU states,
# corrupted and foreign serialized states, many live instances) fails on any invalid read or write
# and on any definite leak. About 50 times slower than natively, hence the few sequences and the
# raised hang limit.
#
#   bash scripts/valgrind.sh [SEQUENCES]      (default 300)
set -euo pipefail
cd "$(dirname "$0")/.."
command -v valgrind > /dev/null || { echo "valgrind is missing: apt-get install valgrind" >&2; exit 1; }
export CARGO_TARGET_X86_64_UNKNOWN_LINUX_GNU_RUNNER="valgrind --quiet --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite --show-leak-kinds=definite"
export CALL_SEQUENCES="${1:-300}" CALL_SEQUENCES_HANG_SECONDS=120
echo "+ valgrind: CALL_SEQUENCES=$CALL_SEQUENCES cargo test --release --test integration call_sequences::"
cargo test --release --test integration call_sequences:: -- --nocapture
