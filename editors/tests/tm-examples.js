// Editor support: every examples/**/*.scn highlights with no invalid.* scope in the TextMate
// grammar (editors/vscode/syntaxes/scn.tmLanguage.json), tokenized by vscode-textmate with the
// oniguruma build VS Code itself uses. Run by .ci/run (npm test in editors/).
"use strict";
const fs = require("fs");
const path = require("path");
const vsctm = require("vscode-textmate");
const oniguruma = require("vscode-oniguruma");

const root = path.join(__dirname, "..", "..");
const wasm = fs.readFileSync(path.join(path.dirname(require.resolve("vscode-oniguruma")), "onig.wasm")).buffer;
const grammarPath = path.join(root, "editors", "vscode", "syntaxes", "scn.tmLanguage.json");

function scnFiles(dir) {
  return fs.readdirSync(dir, { withFileTypes: true }).flatMap((e) => {
    const p = path.join(dir, e.name);
    return e.isDirectory() ? scnFiles(p) : p.endsWith(".scn") ? [p] : [];
  });
}

async function main() {
  await oniguruma.loadWASM(wasm);
  const registry = new vsctm.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (s) => new oniguruma.OnigScanner(s),
      createOnigString: (s) => new oniguruma.OnigString(s),
    }),
    loadGrammar: async (scope) =>
      scope === "source.scn"
        ? vsctm.parseRawGrammar(fs.readFileSync(grammarPath, "utf8"), grammarPath)
        : null,
  });
  const grammar = await registry.loadGrammar("source.scn");
  const files = scnFiles(path.join(root, "examples"));
  let failures = 0;
  // A stray character must be flagged, or this check could never fail.
  const probe = grammar.tokenizeLine("camera c { fov 40deg ; }", vsctm.INITIAL);
  if (!probe.tokens.some((t) => t.scopes.includes("invalid.illegal.character.scn"))) {
    console.error("probe: a stray ';' was not highlighted invalid");
    failures++;
  }
  for (const f of files) {
    let stack = vsctm.INITIAL;
    fs.readFileSync(f, "utf8").split(/\r?\n/).forEach((line, n) => {
      const r = grammar.tokenizeLine(line, stack);
      stack = r.ruleStack;
      for (const t of r.tokens) {
        if (t.scopes.some((s) => s.startsWith("invalid"))) {
          console.error(`${path.relative(root, f)}:${n + 1}:${t.startIndex + 1}: ${t.scopes.join(" ")}`);
          failures++;
        }
      }
    });
  }
  console.log(`TextMate grammar over ${files.length} examples: ${failures === 0 ? "no invalid scopes" : failures + " invalid tokens"}`);
  process.exit(failures === 0 ? 0 : 1);
}
main().catch((e) => { console.error(e); process.exit(1); });
