#!/usr/bin/env bash
# One test of the editor packages, as ctest runs it (editors/CMakeLists.txt):
#   run-test.sh NAME MOIRE_BINARY BUILD_DIR
# A test that needs a program this machine lacks (node and npm, vim, nvim, emacs) or a
# subcommand this moire lacks (lsp, fmt) prints "skipped: REASON" and exits 77, which ctest
# reports as skipped; with the program there it runs and passes or fails.
set -euo pipefail
name=$1
moire=$(realpath "$2")
build=$(realpath "$3")
editors=$(cd "$(dirname "$0")/.." && pwd)
root=$(dirname "$editors")
vscode=$editors/vscode
export MOIRE_BINARY=$moire

skip() {
  echo "skipped: $*"
  exit 77
}
need() {
  for p in "$@"; do
    command -v "$p" >/dev/null || skip "$p is not installed (scripts/deps.sh installs it)"
  done
}
# Whether `moire --help` lists the subcommand $1.
has_subcommand() {
  "$moire" --help | sed -n '/^Subcommands:/,/^$/p' | grep -qE "^  $1( |$)"
}
# The names moire gives, in a file, for the editors' own tests.
names_json() {
  local out=$build/editors/names.json
  mkdir -p "$build/editors"
  "$moire" names --json >"$out.tmp" && mv "$out.tmp" "$out"
  echo "$out"
}

case $name in
  names)
    # The generated parts of the grammar, the Vim syntax and the Emacs mode are what
    # `moire names` gives now.
    need node
    node "$root/scripts/gen-editor-names.mjs" --moire "$moire" --check
    ;;
  npm-ci)
    # npm ci, unless node_modules already holds exactly the lockfile's packages.
    need node npm
    cd "$vscode"
    stamp=node_modules/.moire-package-lock.json
    if [[ -f $stamp ]] && cmp -s "$stamp" package-lock.json; then
      echo "npm-ci: node_modules is the lockfile's"
      exit 0
    fi
    npm ci --ignore-scripts --no-audit --no-fund
    cp package-lock.json "$stamp"
    ;;
  tsc)
    need node npm
    cd "$vscode"
    node_modules/.bin/tsc -p .
    ;;
  unit)
    need node npm
    cd "$vscode"
    node --test test/moirePath.test.mjs test/settings.test.mjs test/commands.test.mjs \
      test/grammar-names.test.mjs test/snippets.test.mjs
    ;;
  server)
    # The extension starts `moire lsp` and it answers; until moire has the server, skipped.
    need node npm
    has_subcommand lsp || skip "$moire has no lsp subcommand (the language server is not built in)"
    cd "$vscode"
    node --test test/server.test.mjs
    ;;
  grammar-snapshots)
    need node npm
    cd "$vscode"
    node test/grammar-snapshots.mjs
    ;;
  vsix)
    need node npm python3
    cd "$vscode"
    vsix=$build/editors/moire.vsix
    mkdir -p "$build/editors"
    rm -f "$vsix"
    node_modules/.bin/vsce package --skip-license --allow-missing-repository --out "$vsix"
    python3 "$editors/test/check-vsix.py" "$vsix" "$vscode/package.json"
    ;;
  vim)
    need vim
    out=$(mktemp)
    trap 'rm -f "$out"' EXIT
    status=0
    MOIRE_EDITORS=$editors/ MOIRE_NAMES=$(names_json) MOIRE_OUT=$out \
      vim -N -u NONE -i NONE -n -es -S "$editors/vim/test/run.vim" </dev/null || status=$?
    cat "$out"
    [[ $status -eq 0 && ! -s $out ]] || { echo "vim: FAILED"; exit 1; }
    echo "vim: the syntax, ftplugin and indent of editors/vim behave"
    ;;
  nvim)
    need nvim
    out=$(mktemp)
    trap 'rm -f "$out"' EXIT
    status=0
    MOIRE_EDITORS=$editors MOIRE_OUT=$out nvim --headless -u NONE -i NONE \
      --cmd "set rtp^=$editors/nvim" -c "luafile $editors/nvim/test/run.lua" </dev/null || status=$?
    cat "$out"
    [[ $status -eq 0 && ! -s $out ]] || { echo "nvim: FAILED"; exit 1; }
    echo "nvim: editors/nvim shares editors/vim and registers moire lsp with lspconfig"
    ;;
  emacs)
    need emacs
    # It byte-compiles without a warning (in a scratch folder: no .elc beside the source).
    work=$(mktemp -d)
    trap 'rm -rf "$work"' EXIT
    cp "$editors/emacs/moire-mode.el" "$work/"
    emacs -Q --batch --eval '(setq byte-compile-error-on-warn t)' -f batch-byte-compile \
      "$work/moire-mode.el"
    MOIRE_EDITORS=$editors MOIRE_NAMES=$(names_json) emacs -Q --batch -l "$editors/emacs/test/run.el"
    echo "emacs: moire-mode behaves"
    ;;
  fmt)
    # What the Vim package's formatprg and the Emacs mode's moire-format-buffer run:
    # `moire fmt -`, the scene on standard input, the formatted scene on standard output.
    has_subcommand fmt || skip "$moire has no fmt subcommand (the formatter is not built in)"
    for scene in "$root"/examples/*.moire; do
      once=$("$moire" fmt - <"$scene")
      twice=$("$moire" fmt - <<<"$once")
      [[ -n $once && $once == "$twice" ]] || { echo "fmt: moire fmt - is not stable on $scene"; exit 1; }
      "$moire" check - <<<"$once" >/dev/null || { echo "fmt: moire fmt - broke $scene"; exit 1; }
    done
    # The editors run it so: Vim's gq (formatprg) and Emacs's moire-format-buffer give
    # the formatter's output, and leave a scene it refuses as it was.
    scene=$root/examples/two_fields.moire
    want=$("$moire" fmt - <"$scene")
    work=$(mktemp -d)
    trap 'rm -rf "$work"' EXIT
    mkdir "$work/bin"
    ln -s "$moire" "$work/bin/moire"
    export PATH=$work/bin:$PATH
    if command -v vim >/dev/null; then
      cp "$scene" "$work/vim.moire"
      vim -N -u NONE -i NONE -n -es --cmd "set rtp^=$editors/vim" --cmd 'filetype plugin on' \
        -c 'normal! gggqG' -c 'wq' "$work/vim.moire" </dev/null
      [[ $(cat "$work/vim.moire") == "$want" ]] || { echo "fmt: Vim's gq is not moire fmt's"; exit 1; }
    else
      echo "fmt: no vim here; its gq is not tried"
    fi
    if command -v emacs >/dev/null; then
      emacs -Q --batch --eval "(progn (add-to-list 'load-path \"$editors/emacs\"))" \
        -l moire-mode --eval "(progn
          (find-file \"$scene\") (moire-format-buffer)
          (write-region nil nil \"$work/emacs.moire\")
          (erase-buffer) (insert \"layer { family = \")
          (moire-format-buffer)
          (unless (equal (buffer-string) \"layer { family = \") (kill-emacs 1)))"
      [[ $(cat "$work/emacs.moire") == "$want" ]] ||
        { echo "fmt: Emacs's moire-format-buffer is not moire fmt's"; exit 1; }
    else
      echo "fmt: no emacs here; its moire-format-buffer is not tried"
    fi
    echo "fmt: moire fmt - formats every example through a pipe, and the editors run it"
    ;;
  *)
    echo "run-test.sh: no test named '$name'" >&2
    exit 2
    ;;
esac
