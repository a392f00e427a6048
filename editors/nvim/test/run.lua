-- nvim --headless -u NONE -l is not in Neovim 0.7; run as
--   nvim --headless -u NONE -i NONE --cmd 'set rtp^=EDITORS/nvim' -c 'luafile test/run.lua'
-- with MOIRE_EDITORS (the editors/ folder) and MOIRE_OUT (where failures are written).
-- Checks that setup() shares editors/vim (filetype, syntax, indent), and that the
-- lspconfig entry starts `moire lsp` (against a stand-in lspconfig: nvim-lspconfig is not
-- a Debian package).
local errors = {}
local function expect(ok, what)
  if not ok then table.insert(errors, what) end
end

-- Stand-ins for lspconfig's modules: what register() and setup() use of them.
local set_up = nil
package.loaded['lspconfig.util'] = { find_git_ancestor = function() return nil end }
package.loaded['lspconfig.configs'] = {}
package.loaded['lspconfig'] = setmetatable({}, {
  __index = function(_, name)
    return { setup = function(opts) set_up = { name = name, opts = opts } end }
  end,
})

vim.cmd('filetype plugin indent on')
vim.cmd('syntax on')
require('moire').setup({ on_attach = 'x' })
local dir = os.getenv('MOIRE_EDITORS')
vim.cmd('edit ' .. vim.fn.fnameescape(dir .. '/test/sample.moire'))
expect(vim.bo.filetype == 'moire', 'filetype is ' .. vim.bo.filetype)
local function group(lnum, word)
  local col = vim.fn.stridx(vim.fn.getline(lnum), word) + 1
  return vim.fn.synIDattr(vim.fn.synID(lnum, col, 1), 'name')
end
expect(group(8, 'pencil') == 'moireFamily', 'pencil is ' .. group(8, 'pencil'))
expect(group(8, 'field') == 'moireProperty', 'field = is ' .. group(8, 'field'))
expect(group(10, 'px') == 'moireParamUnit', 'a param\'s unit is ' .. group(10, 'px'))
expect(group(10, '..') == 'moireRange', 'a param\'s .. is ' .. group(10, '..'))
expect(vim.bo.commentstring == '// %s', 'commentstring is ' .. vim.bo.commentstring)
expect(vim.bo.indentexpr:match('MoireIndent') ~= nil, 'indentexpr is ' .. vim.bo.indentexpr)
local entry = package.loaded['lspconfig.configs'].moire
expect(entry ~= nil, 'no configs.moire')
if entry then
  expect(vim.deep_equal(entry.default_config.cmd, { 'moire', 'lsp' }), 'cmd is ' .. vim.inspect(entry.default_config.cmd))
  expect(vim.deep_equal(entry.default_config.filetypes, { 'moire' }), 'filetypes')
  expect(entry.default_config.root_dir('/tmp/x/scene.moire') == '/tmp/x', 'root_dir')
end
expect(set_up and set_up.name == 'moire' and set_up.opts.on_attach == 'x', 'lspconfig.moire.setup was not called with the options')
expect(vim.v.errmsg == '', 'Neovim said: ' .. vim.v.errmsg)
vim.fn.writefile(errors, os.getenv('MOIRE_OUT'))
vim.cmd(#errors == 0 and 'qall!' or 'cquit!')
