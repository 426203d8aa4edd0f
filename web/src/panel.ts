// The page's panel of every scene key, built from the schema (src/generated/schema.json, the
// one declaration of src/scene/mod.rs): a section per table, a control per key with the
// desktop explorer's slider where the schema gives one (linear or logarithmic, the same ends),
// a number field beside it that takes any value the key's range allows, a switch, a menu of the
// choices, a field of comma-separated numbers for a vector, or a text field for a file's path. An edit is handed on as the
// key's value in TOML syntax (what `--set KEY=VALUE` takes), which the loader's twin checks.

import { type Key, SCHEMA, type Scene, displayFloat } from './scene';

/// A slider's steps between its ends.
const STEPS = 1000;

export type Edit = (path: string, value: string) => void;

interface Control {
  key: Key;
  show(value: number | string | boolean | number[]): void;
}

/// A value in TOML syntax as `--set` takes it.
export function tomlOf(key: Key, value: number | string | boolean | number[]): string {
  if (Array.isArray(value)) return `[${value.map(displayFloat).join(', ')}]`;
  if (typeof value === 'number') return key.type === 'integer' ? String(Math.round(value)) : displayFloat(value);
  if (typeof value === 'string') return JSON.stringify(value);
  return String(value);
}

export class Panel {
  private controls: Control[] = [];

  constructor(
    root: HTMLElement,
    private edit: Edit,
  ) {
    for (const table of SCHEMA.tables) {
      const section = document.createElement('details');
      section.dataset.table = table.name;
      const summary = document.createElement('summary');
      summary.textContent = table.name;
      if (table.readme) summary.title = table.readme;
      section.append(summary);
      for (const key of SCHEMA.keys.filter((k) => k.table === table.name)) {
        section.append(this.row(key));
      }
      root.append(section);
    }
    root.querySelector<HTMLDetailsElement>('details[data-table="fractal"]')!.open = true;
  }

  /// Shows the scene's values.
  show(scene: Scene): void {
    for (const c of this.controls) c.show(scene.get(c.key.path)!);
  }

  private row(key: Key): HTMLElement {
    const row = document.createElement('div');
    row.className = 'row';
    const label = document.createElement('label');
    label.textContent = key.name;
    label.title = `${key.path}: ${key.readme}`;
    row.append(label);
    const id = `key-${key.path.replace('.', '-')}`;
    label.htmlFor = id;
    const send = (v: number | string | boolean | number[]) => this.edit(key.path, tomlOf(key, v));
    switch (key.type) {
      case 'bool': {
        const box = input('checkbox', id);
        box.addEventListener('change', () => send(box.checked));
        row.append(box);
        row.classList.add('wide');
        this.controls.push({ key, show: (v) => (box.checked = v as boolean) });
        break;
      }
      case 'choice': {
        const menu = document.createElement('select');
        menu.id = id;
        for (const c of key.choices ?? []) menu.append(new Option(c, c));
        menu.addEventListener('change', () => send(menu.value));
        row.append(menu);
        row.classList.add('wide');
        this.controls.push({ key, show: (v) => (menu.value = v as string) });
        break;
      }
      case 'path': {
        const field = input('text', id);
        field.addEventListener('change', () => send(field.value));
        row.append(field);
        row.classList.add('wide');
        this.controls.push({ key, show: (v) => (field.value = v as string) });
        break;
      }
      case 'vector':
      case 'hyper': {
        const field = input('text', id);
        field.addEventListener('change', () => {
          const items = field.value.split(',').map((x) => x.trim());
          const numbers = items.map(Number);
          // Not numbers: hand the text on as it is, for the loader to refuse in its words.
          if (numbers.some((x, k) => items[k] === '' || Number.isNaN(x))) this.edit(key.path, `[${field.value}]`);
          else send(numbers);
        });
        row.append(field);
        row.classList.add('wide');
        this.controls.push({ key, show: (v) => (field.value = (v as number[]).map(displayFloat).join(', ')) });
        break;
      }
      default: {
        const slider = key.slider ?? null;
        const range = input('range', `${id}-slider`);
        range.min = '0';
        range.max = String(STEPS);
        range.setAttribute('aria-label', `${key.path} slider`);
        const field = input('number', id);
        field.step = key.type === 'integer' ? '1' : 'any';
        const ofRange = (t: number) => {
          if (slider === null) return NaN;
          const f = t / STEPS;
          const v = slider.logarithmic
            ? Math.exp(Math.log(slider.min) + f * (Math.log(slider.max) - Math.log(slider.min)))
            : slider.min + f * (slider.max - slider.min);
          return key.type === 'integer' ? Math.round(v) : Number(v.toPrecision(6));
        };
        const toRange = (v: number) => {
          if (slider === null) return 0;
          const f = slider.logarithmic
            ? (Math.log(Math.max(v, slider.min)) - Math.log(slider.min)) / (Math.log(slider.max) - Math.log(slider.min))
            : (v - slider.min) / (slider.max - slider.min);
          return Math.round(Math.min(Math.max(f, 0), 1) * STEPS);
        };
        range.addEventListener('input', () => send(ofRange(Number(range.value))));
        field.addEventListener('change', () => {
          if (field.value.trim() === '') return;
          // What the user typed, as TOML: the loader tells integers from floats and says why a
          // value is out of range, in the CLI's words.
          const typed = Number(field.value);
          this.edit(key.path, Number.isNaN(typed) ? JSON.stringify(field.value) : tomlOf(key, typed));
        });
        if (slider !== null) row.append(range);
        else row.classList.add('wide');
        row.append(field);
        this.controls.push({
          key,
          show: (v) => {
            field.value = key.type === 'integer' ? String(v) : displayFloat(v as number);
            range.value = String(toRange(v as number));
          },
        });
      }
    }
    return row;
  }
}

function input(type: string, id: string): HTMLInputElement {
  const e = document.createElement('input');
  e.type = type;
  e.id = id;
  return e;
}
