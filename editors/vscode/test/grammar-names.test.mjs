// The TextMate grammar highlights every name the compiler knows (`moire names --json` of the
// real binary) as its kind, and the places where one spelling means two things.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { before, test } from 'node:test';
import { loadGrammar, scopesAt } from './grammar.mjs';
import { moire, sourceRoot } from './support.mjs';

let grammar;
before(async () => {
  grammar = await loadGrammar();
});

const names = JSON.parse(execFileSync(moire, ['names', '--json'], { encoding: 'utf8' }));

// The innermost scope of `word` (its first place at or after `from`) in `line`.
function scopeOf(line, word, from = 0) {
  const col = line.indexOf(word, from);
  assert.ok(col >= 0, `'${word}' is not in '${line}'`);
  return scopesAt(grammar, line, col).at(-1);
}

const cases = [
  ['keywords', 'keyword.declaration.moire', (n) => [`${n} {`, 0]],
  ['properties', 'support.type.property-name.moire', (n) => [`${n} = 1`, 0]],
  ['functions', 'support.function.moire', (n) => [`a = ${n}(1)`, 4]],
  ['fields', 'support.variable.field.moire', (n) => [`a = ${n}`, 4]],
  ['easings', 'support.constant.easing.moire', (n) => [`a = ${n}`, 4]],
  ['constants', 'constant.language.moire', (n) => [`a = ${n}`, 4]],
  ['variables', 'variable.language.moire', (n) => [`a = ${n}`, 4]],
  ['words', 'constant.language.word.moire', (n) => [`a = ${n}`, 4]],
];

for (const [kind, scope, context] of cases) {
  test(`every one of moire's ${kind} is ${scope}`, () => {
    assert.ok(names[kind].length > 0);
    for (const name of names[kind]) {
      const [line, from] = context(name);
      assert.equal(scopeOf(line, name, from), scope, line);
    }
  });
}

test('every family is a family, and every unit a unit', () => {
  for (const { name } of names.families) assert.equal(scopeOf(`family = ${name}`, name, 9), 'support.class.family.moire');
  for (const unit of names.units) {
    assert.equal(scopeOf(`rotation = 30${unit}`, unit, 11), 'keyword.other.unit.moire');
    assert.equal(scopeOf(`rotation = 30${unit}`, '30', 11), 'constant.numeric.moire');
  }
});

test('one spelling, two meanings: each is told apart by where it stands', () => {
  const sample = readFileSync(join(sourceRoot, 'editors/test/sample.moire'), 'utf8').split('\n');
  assert.equal(scopeOf(sample[1], 'field'), 'keyword.declaration.moire');
  assert.equal(scopeOf(sample[1], 'bump'), 'entity.name.moire');
  assert.equal(scopeOf(sample[2], 'depth'), 'variable.parameter.moire');
  assert.equal(scopeOf(sample[3], 'w'), 'variable.other.definition.moire');
  assert.equal(scopeOf(sample[6], 'easing'), 'support.type.property-name.moire');
  assert.equal(scopeOf(sample[7], 'family'), 'support.type.property-name.moire');
  assert.equal(scopeOf(sample[7], 'pencil'), 'support.class.family.moire');
  assert.equal(scopeOf(sample[7], 'lines'), 'variable.parameter.moire'); // the pencil's parameter
  assert.equal(scopeOf(sample[7], 'field'), 'support.type.property-name.moire');
  assert.equal(scopeOf(sample[7], '#18181c'), 'constant.other.color.moire');
  assert.equal(scopeOf(sample[8], 'spacing'), 'comment.block.moire');
  assert.equal(scopeOf('a = 2e-3', '2e-3'), 'constant.numeric.moire');
  // A param: the function step in its value, then its range, step and unit; after a `;` the
  // words are names again.
  const param = [
    [9, 'param', 'keyword.declaration.moire'],
    [9, 'gap', 'entity.name.moire'],
    [9, 'step', 'support.function.moire'],
    [9, 'in', 'keyword.other.param.moire'],
    [9, '0', 'constant.numeric.moire', 29],
    [9, '..', 'keyword.operator.range.moire'],
    [9, '20', 'constant.numeric.moire'],
    [9, 'step', 'keyword.other.param.moire', 20],
    [9, '0.5', 'constant.numeric.moire'],
    [9, 'unit', 'keyword.other.param.moire'],
    [9, 'px', 'keyword.other.unit.moire'],
    [10, 'bold', 'entity.name.moire'],
    [10, 'true', 'constant.language.word.moire'],
    [10, 'in', 'entity.name.moire'],
    [10, 'select', 'support.function.moire'],
  ];
  for (const [line, word, scope, from] of param) assert.equal(scopeOf(sample[line], word, from), scope, word);
  assert.equal(scopeOf('a = 1.5..2', '1.5'), 'constant.numeric.moire');
  assert.equal(scopeOf('a = .5', '.5'), 'constant.numeric.moire');
});
