# Sourced by the node test runners (tests/lsp/run.sh, tests/web/run.sh): skips the test
# (exit 77, with the reason) when node or npm is missing, then installs the pinned packages of
# PACKAGE_DIR's package-lock.json into WORK_DIR with `npm ci`, once per lockfile (from npm's
# cache when it has them), one install at a time when several tests share WORK_DIR.
#   npm_modules PACKAGE_DIR WORK_DIR
npm_modules() {
  local package=$1 work=$2 tool
  for tool in node npm; do
    if ! command -v "$tool" >/dev/null; then
      echo "skipped: $tool is not installed (scripts/deps.sh installs nodejs and npm)"
      exit 77
    fi
  done
  mkdir -p "$work"
  exec 9>"$work/.install.lock"
  flock 9
  if ! cmp -s "$package/package-lock.json" "$work/package-lock.json" ||
     [[ ! -d "$work/node_modules" ]]; then
    cp "$package/package.json" "$package/package-lock.json" "$work/"
    (cd "$work" && npm ci --prefer-offline --no-audit --no-fund --loglevel=error)
  fi
  flock -u 9
  export NODE_PATH="$work/node_modules"
}
