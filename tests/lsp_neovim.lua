-- Driven by tests/lsp_neovim.rs: headless Neovim opens a scene, attaches `scnc lsp` as a real
-- client, and records a diagnostic, a hover, a go-to-definition and a formatting result as JSON
-- for the Rust test to assert. Works on Neovim 0.7 (Debian 12) and later. Every wait is bounded;
-- whatever happens, the results so far are written and Neovim quits.
local bin, scene, out = os.getenv("SCNC_BIN"), os.getenv("SCNC_SCENE"), os.getenv("SCNC_OUT")
local results = { steps = {} }

local function step(name) table.insert(results.steps, name) end

-- The position (0-based line, UTF-16 column; ASCII here) `into` bytes into the first line
-- holding `needle`.
local function position_of(buf, needle, into)
  for i, line in ipairs(vim.api.nvim_buf_get_lines(buf, 0, -1, false)) do
    local col = line:find(needle, 1, true)
    if col then return { line = i - 1, character = col - 1 + into } end
  end
  error("not in the buffer: " .. needle)
end

local function run()
  vim.cmd("edit " .. vim.fn.fnameescape(scene))
  local buf = vim.api.nvim_get_current_buf()
  local initialized = false
  local id = vim.lsp.start_client({
    name = "scnc",
    cmd = { bin, "lsp" },
    root_dir = vim.fn.fnamemodify(scene, ":h"),
    on_init = function() initialized = true end,
  })
  assert(id, "scnc lsp started")
  vim.lsp.buf_attach_client(buf, id)
  assert(vim.wait(10000, function() return initialized end, 20), "initialized within 10 s")
  local client = vim.lsp.get_client_by_id(id)
  step("attached")

  -- A diagnostic: an unknown name typed at the end (unformatted, for the formatting below).
  vim.api.nvim_buf_set_lines(buf, -1, -1, false, { "let broken=nope" })
  assert(vim.wait(10000, function() return #vim.diagnostic.get(buf) > 0 end, 20),
    "a diagnostic within 10 s")
  local d = vim.diagnostic.get(buf)[1]
  local lsp_data = d.user_data and d.user_data.lsp or {}
  results.diagnostic = {
    lnum = d.lnum, col = d.col, end_col = d.end_col, message = d.message,
    code = d.code or lsp_data.code,
  }
  step("diagnostic")

  local function request(method, params)
    local response, err = client.request_sync(method, params, 10000, buf)
    assert(response, method .. ": " .. tostring(err))
    assert(not response.err, method .. ": " .. vim.inspect(response.err))
    return response.result
  end
  local document = { uri = vim.uri_from_bufnr(buf) }

  local hover = request("textDocument/hover",
    { textDocument = document, position = position_of(buf, "fov", 1) })
  results.hover = { value = hover.contents.value, range = hover.range }
  step("hover")

  results.definition_provider = client.server_capabilities.definitionProvider and true or false
  local definition = results.definition_provider and request("textDocument/definition",
    { textDocument = document, position = position_of(buf, "material matte", 10) })
  if definition and definition[1] then definition = definition[1] end
  results.definition = definition and { uri = definition.uri or definition.targetUri,
    range = definition.range or definition.targetSelectionRange }
  step("definition")

  local edits = request("textDocument/formatting",
    { textDocument = document, options = { tabSize = 2, insertSpaces = true } })
  vim.lsp.util.apply_text_edits(edits, buf, "utf-16")
  results.formatted = table.concat(vim.api.nvim_buf_get_lines(buf, 0, -1, false), "\n") .. "\n"
  step("formatting")
end

local ok, err = pcall(run)
if not ok then results.error = tostring(err) end
local file = assert(io.open(out, "w"))
file:write(vim.fn.json_encode(results))
file:close()
vim.cmd("qa!")
