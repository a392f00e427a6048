#!/usr/bin/env python3
# The packaged extension holds what VS Code needs to run it and nothing of its sources or
# tests: check-vsix.py MOIRE.vsix PACKAGE.json
import json
import sys
import zipfile

vsix, manifest_path = sys.argv[1], sys.argv[2]
problems = []
with zipfile.ZipFile(vsix) as z:
    names = set(z.namelist())
    for needed in [
        "extension.vsixmanifest",
        "extension/package.json",
        "extension/out/extension.js",
        "extension/out/commands.js",
        "extension/out/moirePath.js",
        "extension/out/preview.js",
        "extension/out/server.js",
        "extension/out/settings.js",
        "extension/syntaxes/moire.tmLanguage.json",
        "extension/language-configuration.json",
        "extension/snippets/moire.json",
        "extension/node_modules/vscode-languageclient/package.json",
    ]:
        if needed not in names:
            problems.append(f"{needed} is missing")
    for name in names:
        for unwanted in ("extension/src/", "extension/test/", "extension/node_modules/typescript/",
                         "extension/node_modules/@vscode/vsce/", "extension/tsconfig.json"):
            if name.startswith(unwanted):
                problems.append(f"{name} should not be packaged")
    packaged = json.loads(z.read("extension/package.json"))
    source = json.load(open(manifest_path, encoding="utf-8"))
    for key in ("name", "publisher", "version", "main", "contributes", "engines"):
        if packaged.get(key) != source.get(key):
            problems.append(f"package.json's {key} differs from the source's")
    vsixmanifest = z.read("extension.vsixmanifest").decode("utf-8")
    if f'Id="{source["name"]}"' not in vsixmanifest or f'Publisher="{source["publisher"]}"' not in vsixmanifest:
        problems.append("the vsixmanifest does not name the extension")
    grammar = json.loads(z.read("extension/syntaxes/moire.tmLanguage.json"))
    if grammar.get("scopeName") != "source.moire":
        problems.append("the packaged grammar is not source.moire")
for p in sorted(set(problems)):
    print(f"check-vsix: {p}")
print(f"check-vsix: {'FAILED' if problems else 'the package holds the extension'} ({len(names)} files)")
sys.exit(1 if problems else 0)
