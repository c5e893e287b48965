#!/usr/bin/env python3
"""Renders the benchmark scenes' triangles with Mesa's llvmpipe, plain and with MSAA.

The CPU renderer a user could run instead of the golden model, on the same triangles
(written by `cargo run --release -p pixelproc-bench --example export_tris -- DIR`): a
1920x1080 colour + depth framebuffer, depth test LESS, Gouraud colours, no shading
beyond the vertex colours, the time of `runs` frames each ended by glFinish. Prints per
scene the median milliseconds of a plain frame and of 4x MSAA with the resolve
blit (8x where the Mesa release offers it), and the ratio to the plain frame: the figure `pixelproc bench --all-methods`
reports for its anti-aliasing methods.

Needs: `apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri` and `pip install
moderngl==5.13.0`. Usage: llvmpipe.py DIR [--runs N] (N >= 1, default 9).
"""
import argparse
import os
import statistics
import struct
import sys
import time


def load(path):
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 12:
        sys.exit(f"error: {path}: shorter than its 12-byte header")
    w, h, n = struct.unpack_from("<III", data, 0)
    if len(data) != 12 + n * 84:
        sys.exit(f"error: {path}: {len(data)} bytes, header says {n} triangles ({12 + n * 84})")
    return w, h, n, data[12:]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir", help="folder of .tris files written by the export_tris example")
    ap.add_argument("--runs", type=int, default=9, help="timed frames per case (default 9)")
    a = ap.parse_args()
    if a.runs < 1:
        sys.exit("error: --runs must be at least 1")
    names = sorted(p for p in os.listdir(a.dir) if p.endswith(".tris")) if os.path.isdir(a.dir) else []
    if not names:
        sys.exit(f"error: no .tris files in {a.dir}")
    import moderngl

    ctx = moderngl.create_standalone_context(backend="egl")
    print(f"# {ctx.info['GL_RENDERER']}, {ctx.info['GL_VERSION']}, LP_NUM_THREADS={os.environ.get('LP_NUM_THREADS', 'default')}")
    prog = ctx.program(
        vertex_shader="""
        #version 330
        uniform vec2 size;
        in vec3 pos; in vec3 col;
        out vec3 c;
        void main() {
            // Pixels (y down) to clip space; depth 0..1 to -1..1.
            gl_Position = vec4(pos.x / size.x * 2.0 - 1.0, 1.0 - pos.y / size.y * 2.0, pos.z * 2.0 - 1.0, 1.0);
            c = col;
        }""",
        fragment_shader="""
        #version 330
        in vec3 c; out vec4 o;
        void main() { o = vec4(c, 1.0); }""",
    )
    # llvmpipe offers 4x multisampling (and more only in newer Mesa releases).
    msaa = [s for s in (4, 8) if s <= ctx.max_samples]
    head = "".join(f" {s}x MSAA ms | {s}x × plain |" for s in msaa)
    print(f"| scene | triangles | plain ms |{head}")
    print("|---|---:|---:|" + "---:|---:|" * len(msaa))
    for name in names:
        w, h, n, tris = load(os.path.join(a.dir, name))
        vbo = ctx.buffer(tris)
        vao = ctx.vertex_array(prog, [(vbo, "3f 3f 4x", "pos", "col")])
        prog["size"].value = (float(w), float(h))
        resolve = ctx.simple_framebuffer((w, h))
        times = {}
        for samples in [0] + msaa:
            fbo = ctx.simple_framebuffer((w, h), samples=samples)
            t = []
            for k in range(a.runs + 1):  # the first frame is a warm-up
                t0 = time.perf_counter()
                fbo.use()
                ctx.enable(moderngl.DEPTH_TEST)
                fbo.clear(0.0, 0.0, 0.0, 1.0, depth=1.0)
                vao.render(moderngl.TRIANGLES, vertices=3 * n)
                if samples:
                    ctx.copy_framebuffer(resolve, fbo)
                ctx.finish()
                if k:
                    t.append((time.perf_counter() - t0) * 1000)
            times[samples] = statistics.median(t)
            fbo.release()
        p = times[0]
        cells = "".join(f" {times[s]:.1f} | {times[s] / p:.2f} |" for s in msaa)
        print(f"| {name[:-5]} | {n} | {p:.1f} |{cells}")
        vao.release()
        vbo.release()
        resolve.release()


if __name__ == "__main__":
    main()
