-- The nvim-lspconfig entry for the moire language server: `moire lsp` over stdio, for
-- buffers of filetype moire, rooted at the enclosing git repository or else the file's
-- folder (a scene needs no project).
local M = {}

M.default_config = {
  cmd = { 'moire', 'lsp' },
  filetypes = { 'moire' },
  root_dir = function(fname)
    local util = require('lspconfig.util')
    return util.find_git_ancestor(fname) or vim.fn.fnamemodify(fname, ':p:h')
  end,
  single_file_support = true,
  settings = {},
}

M.docs = {
  description = 'The moire language server (`moire lsp`): diagnostics as `moire check` gives them, hover, completion, go to definition, rename, formatting.',
}

-- Adds `moire` to lspconfig's configs, once.
function M.register()
  local configs = require('lspconfig.configs')
  if not configs.moire then
    configs.moire = { default_config = M.default_config, docs = M.docs }
  end
end

return M
