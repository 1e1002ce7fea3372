// The VS Code client (editors/vscode/extension.js): its manifest declares the activation, the
// entry point and the `scnc.serverPath` setting, pins the same vscode-languageclient as the
// lock file here, and activating it with a stand-in `vscode` module starts `<serverPath> lsp`
// for `.scn` files (and restarts it when the setting changes). Run by .ci/run (npm test).
"use strict";
const assert = require("assert");
const fs = require("fs");
const Module = require("module");
const path = require("path");

const extensionDir = path.join(__dirname, "..", "vscode");
const manifest = JSON.parse(fs.readFileSync(path.join(extensionDir, "package.json"), "utf8"));
const tools = JSON.parse(fs.readFileSync(path.join(__dirname, "..", "package.json"), "utf8"));

function checkManifest() {
  assert.deepStrictEqual(manifest.activationEvents, ["onLanguage:scn"]);
  assert.strictEqual(manifest.main, "./extension.js");
  assert.ok(fs.existsSync(path.join(extensionDir, manifest.main)), "the entry point exists");
  const setting = manifest.contributes.configuration.properties["scnc.serverPath"];
  assert.strictEqual(setting.type, "string");
  assert.strictEqual(setting.default, "scnc");
  const client = manifest.dependencies["vscode-languageclient"];
  assert.strictEqual(client, tools.dependencies["vscode-languageclient"], "one pinned version");
  // The real client library loads (installed by npm ci from the lock file).
  assert.ok(require.resolve("vscode-languageclient/node"));
}

async function checkActivation() {
  const started = [];
  let configured = "/opt/scnc/bin/scnc";
  let onChange = null;
  const vscode = {
    workspace: {
      getConfiguration: (section) => ({
        get: (key, fallback) => (section === "scnc" && key === "serverPath" ? configured : fallback),
      }),
      onDidChangeConfiguration: (listener) => {
        onChange = listener;
        return { dispose() {} };
      },
    },
    window: { showErrorMessage: (m) => assert.fail(`unexpected error message: ${m}`) },
  };
  class LanguageClient {
    constructor(id, name, server, options) {
      Object.assign(this, { id, server, options, running: false });
      started.push(this);
    }
    async start() { this.running = true; }
    async stop() { this.running = false; }
  }
  const load = Module._load;
  Module._load = function (request, ...rest) {
    if (request === "vscode") return vscode;
    if (request === "vscode-languageclient/node") return { LanguageClient };
    return load.call(this, request, ...rest);
  };
  try {
    const extension = require(path.join(extensionDir, "extension.js"));
    const context = { subscriptions: [] };
    await extension.activate(context);
    assert.strictEqual(started.length, 1);
    assert.deepStrictEqual(started[0].server, { command: "/opt/scnc/bin/scnc", args: ["lsp"] });
    assert.deepStrictEqual(started[0].options.documentSelector, [{ scheme: "file", language: "scn" }]);
    assert.ok(started[0].running);
    assert.strictEqual(context.subscriptions.length, 1);

    configured = "";
    await onChange({ affectsConfiguration: (s) => s === "scnc.serverPath" });
    assert.strictEqual(started.length, 2);
    assert.ok(!started[0].running, "the old server is stopped");
    assert.deepStrictEqual(started[1].server, { command: "scnc", args: ["lsp"] });
    await extension.deactivate();
    assert.ok(!started[1].running);
  } finally {
    Module._load = load;
  }
}

checkManifest();
checkActivation().then(
  () => console.log("VS Code client: manifest and activation ok"),
  (e) => { console.error(e); process.exit(1); }
);
