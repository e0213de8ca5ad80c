"""The hostile loader corpus, built in memory.

One module per scene format, so each stays small enough to review; build()
runs them in a fixed order, which is the manifest's order and so part of the
output: make_corpus.py must produce the same bytes run after run.
"""

from __future__ import annotations

from .bases import PNG, TRIANGLE_BIN, Corpus
from .compressed_cases import compressed_cases
from .glb_cases import glb_cases
from .gltf_cases import gltf_cases
from .obj_cases import obj_cases
from .sidecar_cases import sidecar_cases


def build() -> Corpus:
    c = Corpus()
    c.companion("buffer.bin", TRIANGLE_BIN)
    c.companion("sub/buffer.bin", TRIANGLE_BIN)
    c.companion("image.png", PNG)
    gltf_cases(c)
    glb_cases(c)
    compressed_cases(c)
    obj_cases(c)
    sidecar_cases(c)
    return c
