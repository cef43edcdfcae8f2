#!/usr/bin/env bash
# Every test of the workspace, as CI runs them, on a fresh Debian machine: first installs what the
# tests use when it is missing, then runs the checks cheapest first and stops at the first failure.
#
# Usage: bash scripts/test.sh [--quick]
#   --quick   leave out the MSRV check, the benchmarks' build, the portable and AVX2 node
#             tests' reruns, the Python package's tests and the Slurm cluster test (and what
#             only they install)
#
# Installing needs root (apt-get) and npm's registry; elsewhere a missing tool fails here, naming what to install.
# A test never passes by skipping: without its tool it fails.
set -euo pipefail
cd "$(dirname "$0")/.."

quick=0
for arg in "$@"; do
  case $arg in
    --quick) quick=1 ;;
    -h | --help)
      sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'
      exit 0
      ;;
    *)
      echo "scripts/test.sh: unknown option $arg (see --help)" >&2
      exit 2
      ;;
  esac
done

# The Rust version that `rust-version` in Cargo.toml promises.
msrv=1.89

fail() {
  echo "scripts/test.sh: $*" >&2
  exit 1
}

# --- Installing what is missing.

apt_updated=0
# Installs Debian packages, or fails naming them where apt-get cannot run.
apt_install() {
  local why=$1
  shift
  if [[ $EUID -ne 0 ]] || ! command -v apt-get >/dev/null 2>&1; then
    fail "$why is missing: install it with \`apt-get install $*\` (as root), or run this script as root"
  fi
  echo "installing $* ($why)"
  export DEBIAN_FRONTEND=noninteractive
  if [[ $apt_updated -eq 0 ]]; then
    apt-get update -qq
    apt_updated=1
  fi
  apt-get install -y -qq "$@" >/dev/null
}

have_chromium() {
  [[ -n ${CHROMIUM:-} ]] || command -v chromium >/dev/null 2>&1 ||
    command -v chromium-browser >/dev/null 2>&1 || command -v google-chrome >/dev/null 2>&1
}

# Lavapipe, Mesa's software Vulkan driver, and the loader: the GPU pipeline's tests need an adapter.
have_lavapipe() {
  PATH=$PATH:/usr/sbin:/sbin ldconfig -p | grep -q 'libvulkan\.so\.1' &&
    compgen -G '/usr/share/vulkan/icd.d/lvp_icd*.json' >/dev/null
}

have_slurm() {
  local cmd
  for cmd in munged slurmctld slurmd sbatch squeue scontrol sinfo; do
    command -v "$cmd" >/dev/null 2>&1 || return 1
  done
}

install_rust_parts() {
  if ! cargo fmt --version >/dev/null 2>&1 || ! cargo clippy --version >/dev/null 2>&1; then
    echo "installing rustfmt and clippy"
    rustup component add rustfmt clippy
  fi
  if [[ $quick -eq 0 ]] && ! rustup run "$msrv" cargo --version >/dev/null 2>&1; then
    echo "installing Rust $msrv (the MSRV check)"
    rustup toolchain install "$msrv" --profile minimal
  fi
}

# The Python package's tests run in their own environment (no root needed, and Debian's
# system Python refuses packages that pip installs).
python_env() {
  local venv=$target_dir/python-test-env
  if [[ ! -x $venv/bin/python ]]; then
    python3 -m venv "$venv" 2>/dev/null || {
      rm -rf "$venv"
      apt_install "Python's venv module" python3-venv
      python3 -m venv "$venv"
    }
  fi
  python=$venv/bin/python
}

install_missing() {
  install_rust_parts
  have_chromium || apt_install "Chromium (the report page's tests)" chromium
  have_lavapipe || apt_install "a Vulkan driver (the GPU pipeline's tests)" mesa-vulkan-drivers libvulkan1
  command -v npm >/dev/null 2>&1 || apt_install "Node.js and npm (the three.js and Babylon.js engines' tests)" nodejs npm
  # The engines' packages, exactly as their package-lock.json files pin them.
  echo "installing engines/three's packages (npm ci)"
  npm ci --prefix engines/three --no-audit --no-fund --loglevel=error
  echo "installing engines/babylon's packages (npm ci)"
  npm ci --prefix engines/babylon --no-audit --no-fund --loglevel=error
  if [[ $quick -eq 0 ]]; then
    have_slurm ||
      apt_install "Slurm (the cluster test)" --no-install-recommends munge slurmctld slurmd slurm-client
    python_env
  fi
}

# --- The steps.

step_count=0
started_all=$SECONDS
# Runs one step under a header, and prints its wall time; the first failing step ends the script
# with its exit status.
step() {
  local name=$1
  shift
  step_count=$((step_count + 1))
  echo
  echo "==> [$step_count] $name: $*"
  local started=$SECONDS status=0
  "$@" || status=$?
  local took=$((SECONDS - started))
  if [[ $status -ne 0 ]]; then
    echo "<== [$step_count] $name FAILED (exit $status) after ${took} s" >&2
    exit "$status"
  fi
  echo "<== [$step_count] $name passed in ${took} s"
}

# Every cargo command selects the same packages as the test step, which keeps the dependencies'
# features, and so their builds, the same (`-p` alone would build them again).
rust_packages=(--workspace --exclude shadowtruth-py)

# The exactness tests again with the portable node test, which the 8-lane one replaces on
# processors with AVX2 (crates/shadowtruth/src/trace/bvh/node_test.rs), and the packet tests with
# packets of eight alone, as a processor without AVX-512 walks every batch
# (crates/shadowtruth/src/trace/bvh/packet_isa.rs).
other_node_tests() {
  SHADOWTRUTH_NODE_TEST=portable cargo test "${rust_packages[@]}" --release --locked --test trace_traps \
    --test reference_hard_cases --test reference_exact --test instancing --test adjudicator &&
    SHADOWTRUTH_NODE_TEST=avx2 cargo test "${rust_packages[@]}" --release --locked --lib -- packet
}

# The Python package built from this tree, and its tests against the release binary (which the
# tests step built for the command's own tests).
python_tests() {
  [[ -x $target_dir/release/shadowtruth ]] || fail "no $target_dir/release/shadowtruth after the tests"
  # The `test` extra: what the tests import beside the package.
  "$python" -m pip install -q './crates/shadowtruth-py[test]' &&
    SHADOWTRUTH_BIN=$target_dir/release/shadowtruth "$python" -m pytest -q crates/shadowtruth-py/tests
}

# A real single-node Slurm cluster runs the bundled suite as a 4-shard job array and its merge.
slurm_test() {
  [[ $EUID -eq 0 ]] || fail "the Slurm cluster test starts munged, slurmctld and slurmd: run as root"
  SHADOWTRUTH=$target_dir/release/shadowtruth bash crates/shadowtruth-cli/tests/slurm/cluster_test.sh
}

target_dir=$(cargo metadata --format-version 1 --no-deps |
  sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')
[[ -n $target_dir ]] || fail "cargo metadata names no target directory"
install_missing
# Silences a harmless warning of Mesa's device-selection layer.
export NODEVICE_SELECT=1
cargo --version
rustc --version

step "formatting" cargo fmt --all --check
step "clippy" cargo clippy --workspace --all-targets --locked -- -D warnings
# The Python extension is checked (clippy, MSRV) with the rest but not documented, built or tested
# by cargo: its API is Python's (stubs and docstrings), its library is named `shadowtruth` as the
# library is, and it links against the interpreter that pip builds it for (python_tests).
step "rustdoc" env RUSTDOCFLAGS='-D warnings' cargo doc "${rust_packages[@]}" --no-deps --locked
[[ $quick -eq 1 ]] || step "Rust $msrv (MSRV)" cargo "+$msrv" check --workspace --all-targets --locked
# The benchmarks are built, not run, so that they cannot rot.
[[ $quick -eq 1 ]] || step "benchmarks build" cargo bench --no-run "${rust_packages[@]}" --locked
# --- The Bevy engine harness (engines/bevy): a package of its own with its own Cargo.lock and
# target folder, built before the tests because crates/shadowtruth-cli/tests/engine_bevy.rs runs
# its binary (on lavapipe, installed above, where there is no GPU).
bevy_manifest=(--manifest-path engines/bevy/Cargo.toml)
step "Bevy harness: formatting" cargo fmt "${bevy_manifest[@]}" --check
step "Bevy harness: build" cargo build "${bevy_manifest[@]}" --release --locked
# --- End of the Bevy engine harness.

# The unit, integration and doctests (the README's Rust examples among them).
step "tests" cargo test "${rust_packages[@]}" --release --locked
if [[ $quick -eq 0 ]]; then
  step "tests, portable and AVX2 node tests" other_node_tests
  step "Python package" python_tests
  step "Slurm cluster" slurm_test
fi
echo
echo "scripts/test.sh: all $step_count steps passed in $((SECONDS - started_all)) s"
