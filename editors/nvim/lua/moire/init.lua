-- Neovim support for .moire scenes: the Vim package (syntax, ftplugin with :make through
-- `moire check`, indent) shared from editors/vim rather than copied, and the language
-- server `moire lsp` through nvim-lspconfig. Highlighting beyond the Vim syntax comes from
-- the server's semantic tokens.
--
--   vim.opt.runtimepath:append('/path/to/moire/editors/nvim')
--   require('moire').setup()          -- or setup({ cmd = { '/path/to/moire', 'lsp' } })
local M = {}

-- editors/vim, beside the folder this file is in (editors/nvim/lua/moire/init.lua).
function M.vim_dir()
  local here = debug.getinfo(1, 'S').source:sub(2)
  return vim.fn.fnamemodify(here, ':p:h:h:h:h') .. '/vim'
end

-- opts.cmd: the server's command line (default { 'moire', 'lsp' }); opts.lsp = false: no
-- language server; the rest goes to lspconfig's setup (on_attach, capabilities, ...).
function M.setup(opts)
  opts = opts or {}
  local vim_dir = M.vim_dir()
  if not vim.tbl_contains(vim.opt.runtimepath:get(), vim_dir) then
    vim.opt.runtimepath:append(vim_dir)
  end
  if opts.lsp == false then
    return
  end
  local server = vim.tbl_extend('force', {}, opts)
  server.lsp = nil
  local ok, lspconfig = pcall(require, 'lspconfig')
  if not ok then
    vim.notify('moire: nvim-lspconfig is not installed; no language server', vim.log.levels.WARN)
    return
  end
  require('moire.lspconfig').register()
  lspconfig.moire.setup(server)
end

return M
