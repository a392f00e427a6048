// The TextMate grammar loaded as VS Code loads it (vscode-textmate over the Oniguruma
// regular expressions), to tokenize lines in tests.
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join } from 'node:path';
import textmate from 'vscode-textmate';
import oniguruma from 'vscode-oniguruma';
import { here } from './support.mjs';

const require = createRequire(import.meta.url);
export const grammarFile = join(here, '..', 'syntaxes', 'moire.tmLanguage.json');

export async function loadGrammar() {
  const wasm = readFileSync(join(require.resolve('vscode-oniguruma'), '..', 'onig.wasm'));
  await oniguruma.loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength));
  const registry = new textmate.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (patterns) => new oniguruma.OnigScanner(patterns),
      createOnigString: (s) => new oniguruma.OnigString(s),
    }),
    loadGrammar: async (scope) =>
      scope === 'source.moire' ? textmate.parseRawGrammar(readFileSync(grammarFile, 'utf8'), grammarFile) : null,
  });
  return registry.loadGrammar('source.moire');
}

// The scopes of the token that holds column `col` of `line`, innermost last.
export function scopesAt(grammar, line, col) {
  const { tokens } = grammar.tokenizeLine(line, textmate.INITIAL);
  const token = tokens.find((t) => t.startIndex <= col && col < t.endIndex);
  return token ? token.scopes : [];
}
