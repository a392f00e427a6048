// The extension's settings, read through a getter so that tests can hand in plain values.
// No `vscode` import.

export interface MoireSettings {
  path: string; // moire.path
  serverEnabled: boolean; // moire.server.enabled
  renderOutput: string; // moire.render.output: '' or a name with ${stem}
  renderSize: string; // moire.render.size: '' or WIDTHxHEIGHT
  backend: string; // moire.backend: '' or jit, interp, vulkan
  previewSaveAfterPause: number; // moire.preview.saveAfterPause: milliseconds, 0 off
}

export type Getter = (key: string) => unknown;

const backends = ['', 'jit', 'interp', 'vulkan'];

function text(get: Getter, key: string): string {
  const v = get(key);
  return typeof v === 'string' ? v.trim() : '';
}

// The settings, and a complaint for each one that cannot be used (it is then left out).
export function readSettings(get: Getter): { settings: MoireSettings; problems: string[] } {
  const problems: string[] = [];
  const enabled = get('server.enabled');
  const settings: MoireSettings = {
    path: text(get, 'path'),
    serverEnabled: typeof enabled === 'boolean' ? enabled : true,
    renderOutput: text(get, 'render.output'),
    renderSize: text(get, 'render.size'),
    backend: text(get, 'backend'),
    previewSaveAfterPause: 0,
  };
  const pause = get('preview.saveAfterPause');
  if (typeof pause === 'number' && Number.isInteger(pause) && pause >= 0 && pause <= 60000) {
    settings.previewSaveAfterPause = pause;
  } else if (pause !== undefined && pause !== null) {
    problems.push(`moire.preview.saveAfterPause is '${pause}': a whole number of milliseconds, 0 to 60000`);
  }
  if (settings.renderSize !== '' && !/^[0-9]+[xX][0-9]+$/.test(settings.renderSize)) {
    problems.push(`moire.render.size is '${settings.renderSize}': write WIDTHxHEIGHT, as in 1920x1080`);
    settings.renderSize = '';
  }
  if (!backends.includes(settings.backend)) {
    problems.push(`moire.backend is '${settings.backend}': it is jit, interp or vulkan`);
    settings.backend = '';
  }
  if (settings.renderOutput.includes('\0')) {
    problems.push('moire.render.output holds a NUL character');
    settings.renderOutput = '';
  }
  return { settings, problems };
}
