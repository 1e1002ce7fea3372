// @ts-check
// The scn extension's client: on the first `.scn` file it starts `scnc lsp` (the path in the
// `scnc.serverPath` setting, `scnc` on PATH by default) with vscode-languageclient, which then
// shows its diagnostics, hovers, completions and formatting. Restarts when the setting changes.
"use strict";
const vscode = require("vscode");
const { LanguageClient } = require("vscode-languageclient/node");

/** @type {LanguageClient | undefined} */
let client;

/** The configured server binary. */
function serverPath() {
  const configured = vscode.workspace.getConfiguration("scnc").get("serverPath", "scnc");
  return typeof configured === "string" && configured.trim() !== "" ? configured.trim() : "scnc";
}

/** Starts `scnc lsp`; reports (once, not as an exception) when it cannot be started. */
async function start() {
  const command = serverPath();
  /** @type {import("vscode-languageclient/node").ServerOptions} */
  const server = { command, args: ["lsp"] };
  /** @type {import("vscode-languageclient/node").LanguageClientOptions} */
  const options = { documentSelector: [{ scheme: "file", language: "scn" }] };
  client = new LanguageClient("scnc", "scnc lsp", server, options);
  try {
    await client.start();
  } catch (e) {
    client = undefined;
    vscode.window.showErrorMessage(
      `scnc lsp could not start (${command}): set "scnc.serverPath" to the scnc binary. ${e}`
    );
  }
}

/** @param {vscode.ExtensionContext} context */
async function activate(context) {
  context.subscriptions.push(
    vscode.workspace.onDidChangeConfiguration(async (event) => {
      if (event.affectsConfiguration("scnc.serverPath")) {
        await deactivate();
        await start();
      }
    })
  );
  await start();
}

async function deactivate() {
  const running = client;
  client = undefined;
  if (running) {
    await running.stop();
  }
}

module.exports = { activate, deactivate };
