#!/usr/bin/env node
// Writes the language's names, as `moire names --json` prints them from the compiler's own
// tables, into the editor packages' highlighting: the TextMate grammar's `names-*` and
// `number` entries (editors/vscode), the region between the GENERATED markers of the Vim
// syntax (editors/vim, which Neovim shares) and of the Emacs mode (editors/emacs). No package
// keeps a list of its own, so none can drift from the compiler.
//
//   node scripts/gen-editor-names.mjs [--moire PATH] [--check]
//
// PATH is the moire binary (default: build/bin/moire). --check writes nothing and exits 1,
// naming each file that differs from what would be written now (ctest runs it so).
import { execFileSync } from 'node:child_process';
import { readFileSync, writeFileSync } from 'node:fs';
import { dirname, join, relative } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
export const files = {
  grammar: join(root, 'editors/vscode/syntaxes/moire.tmLanguage.json'),
  vim: join(root, 'editors/vim/syntax/moire.vim'),
  emacs: join(root, 'editors/emacs/moire-mode.el'),
};

// Every group of names, for the grammar and the syntax files alike. `families` is a list
// of objects in the JSON; the others are lists of names.
export function groups(names) {
  return {
    keywords: names.keywords,
    properties: names.properties,
    functions: names.functions,
    families: names.families.map((f) => f.name),
    fields: names.fields,
    easings: names.easings,
    constants: names.constants,
    variables: names.variables,
    words: names.words,
  };
}

// Longest first, so that no alternative hides a longer one it begins.
const ordered = (list) => [...new Set(list)].sort((a, b) => b.length - a.length || (a < b ? -1 : 1));

// A number, with its unit as the second capture. A range's `..` is no decimal point: `0..5`
// is 0, `..`, 5 (a number may follow `..`, but not one lone `.`).
const numberRegex = (units) =>
  `(?<![A-Za-z0-9_])(?<![^.]\\.)((?:[0-9]+(?:\\.(?!\\.)[0-9]*)?|\\.[0-9]+)(?:[eE][+-]?[0-9]+)?)(?:(${ordered(units).join('|')})\\b)?`;

export function grammarText(current, names) {
  const g = JSON.parse(current);
  for (const [kind, list] of Object.entries(groups(names))) {
    const entry = g.repository[`names-${kind}`];
    if (!entry) throw new Error(`the grammar has no repository entry names-${kind}`);
    const alternatives = ordered(list).join('|');
    // Properties only where they are set: `field = f` in a layer is the property, `field f =`
    // the keyword.
    entry.match = kind === 'properties' ? `\\b(?:${alternatives})\\b(?=\\s*=)` : `\\b(?:${alternatives})\\b`;
  }
  g.repository.number.match = numberRegex(names.units);
  return JSON.stringify(g, null, 2) + '\n';
}

const vimGroups = {
  keywords: 'moireKeyword',
  functions: 'moireFunction',
  families: 'moireFamily',
  fields: 'moireField',
  easings: 'moireEasing',
  constants: 'moireConstant',
  variables: 'moireVariable',
  words: 'moireWord',
  properties: 'moireProperty',
};

function vimRegion(names) {
  const g = groups(names);
  const lines = [];
  for (const [kind, group] of Object.entries(vimGroups)) {
    if (kind === 'properties') {
      // Any `name =` is a family parameter, set in a layer or declared with its default
      // (wave(amplitude = 10)); a block's own property, matched after it, wins over it. At
      // one place the last match defined wins, so `field = f` in a layer is the property,
      // not the keyword, and `lines = 36` the pencil's parameter, not the family.
      lines.push(`syn match moireParameter '\\<\\h\\w*\\>\\ze\\s*='`);
    }
    const alternatives = ordered(g[kind]).join('\\|');
    const tail = kind === 'properties' ? '\\ze\\s*=' : '';
    lines.push(`syn match ${group} '\\<\\%(${alternatives}\\)\\>${tail}'`);
  }
  const units = ordered(names.units).join('\\|');
  // `0..5` is 0, `..`, 5: a decimal point is never the first of two dots.
  lines.push(`syn match moireNumber '\\%(\\<\\d\\+\\%(\\.\\.\\@!\\d*\\)\\=\\|\\.\\@<!\\.\\d\\+\\)\\%([eE][-+]\\=\\d\\+\\)\\=' nextgroup=moireUnit`);
  lines.push(`syn match moireUnit '\\%(${units}\\)\\>' contained`);
  return lines.join('\n');
}

function emacsRegion(names) {
  const g = groups(names);
  const lines = [];
  const quoted = (list) => list.map((n) => `"${n}"`).join(' ');
  for (const kind of Object.keys(vimGroups))
    lines.push(`(defconst moire-${kind} '(${quoted(g[kind])})\n  "The language's ${kind}, from \`moire names'.")`);
  lines.push(`(defconst moire-units '(${quoted(names.units)})\n  "The units a number may carry, from \`moire names'.")`);
  return lines.join('\n');
}

// Replaces what lies between the BEGIN and END GENERATED lines of `text`.
function replaceRegion(text, region, file) {
  const re = /(^.*BEGIN GENERATED.*\n)([\s\S]*?)(^.*END GENERATED.*$)/m;
  if (!re.test(text)) throw new Error(`${file} has no BEGIN GENERATED ... END GENERATED lines`);
  return text.replace(re, (_, begin, _old, end) => `${begin}${region}\n${end}`);
}

export function generate(names) {
  const out = {};
  out.grammar = grammarText(readFileSync(files.grammar, 'utf8'), names);
  out.vim = replaceRegion(readFileSync(files.vim, 'utf8'), vimRegion(names), files.vim);
  out.emacs = replaceRegion(readFileSync(files.emacs, 'utf8'), emacsRegion(names), files.emacs);
  return out;
}

export function readNames(moire) {
  return JSON.parse(execFileSync(moire, ['names', '--json'], { encoding: 'utf8' }));
}

function main(argv) {
  let moire = join(root, 'build/bin/moire');
  let check = false;
  for (let i = 0; i < argv.length; ++i) {
    if (argv[i] === '--check') check = true;
    else if (argv[i] === '--moire' && i + 1 < argv.length) moire = argv[++i];
    else {
      console.error(`gen-editor-names: unknown argument '${argv[i]}'\nusage: node scripts/gen-editor-names.mjs [--moire PATH] [--check]`);
      return 2;
    }
  }
  const wanted = generate(readNames(moire));
  let stale = 0;
  for (const [key, text] of Object.entries(wanted)) {
    const file = files[key];
    if (readFileSync(file, 'utf8') === text) continue;
    if (check) {
      console.error(`gen-editor-names: ${relative(root, file)} is not what \`moire names\` gives now; run node scripts/gen-editor-names.mjs`);
      ++stale;
    } else {
      writeFileSync(file, text);
      console.log(`gen-editor-names: wrote ${relative(root, file)}`);
    }
  }
  if (check && stale === 0) console.log('gen-editor-names: the editor packages have every name moire knows');
  return stale ? 1 : 0;
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) process.exit(main(process.argv.slice(2)));
