// The page's build: `npm run build` writes dist/, which any static host serves. The kernels are
// the project's own shaders/*.wgsl, imported as text at build time (`?raw`), not copies: the
// server may read the folder above.
import { defineConfig } from 'vite';

export default defineConfig({
  base: './',
  server: { fs: { allow: ['..'] } },
  build: { outDir: 'dist', emptyOutDir: true },
  test: { include: ['test/**/*.test.ts'] },
});
