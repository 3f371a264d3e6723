# Sourced by scripts/setup and bench/fidelity/run: where `scripts/setup --peers` installs the npm
# packages of the benchmarks' web peer (<model-viewer>, puppeteer-core), pinned by
# bench/peers/package-lock.json. bench/collection_bench.py and bench/fidelity/fidelity.mjs compute
# the same folder. Outside the clone so that every worktree and a fresh clone share one install.
peers_lock="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../bench/peers" && pwd)/package-lock.json"
peers_dir="${XDG_CACHE_HOME:-$HOME/.cache}/facet/peers"

# True when peers_dir holds the packages of the repository's lock (not an older one).
peers_ready() {
  cmp -s "$peers_lock" "$peers_dir/package-lock.json" &&
    [ -d "$peers_dir/node_modules/@google/model-viewer" ] && [ -d "$peers_dir/node_modules/puppeteer-core" ]
}
