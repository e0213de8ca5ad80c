"""One rtrender binary for any x86-64: built without -march=native, its SIMD
code confined to the kernels it dispatches at run time (util/cpu_features.h),
and the same image from every path, on this CPU and on an emulated one without
AVX (qemu-user's Nehalem model)."""
import os
import re
import shutil
import subprocess

import pytest

# Registers and mnemonics that only AVX and later have.
AVX_OPERAND = re.compile(r"%[yz]mm\d|%k[0-7]\b")
FUNCTION = re.compile(r"^[0-9a-f]+ <(?P<name>.+)>:$")
# A kernel's demangled name: its return type, then rt::avx2:: or rt::avx512::, before its parameters.
KERNEL = re.compile(r"^[^(]*\brt::avx(2|512)::")
# OpenEXR's capDate attribute: the time of writing, the only byte that may differ.
CAP_DATE = re.compile(rb"capDate\x00string\x00.{4}\d{4}:\d\d:\d\d \d\d:\d\d:\d\d", re.S)


def run(*args, env=None):
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=300,
                          env={**os.environ, **(env or {})})


def avx_functions(binary):
    """Functions of `binary` with an instruction on YMM/ZMM/mask registers or VEX-encoded."""
    listing = run("objdump", "-d", "-C", "--no-show-raw-insn", binary)
    assert listing.returncode == 0, listing.stderr
    found, current = set(), None
    for line in listing.stdout.splitlines():
        match = FUNCTION.match(line)
        if match:
            current = match["name"]
            continue
        parts = line.split("\t")
        if current is None or len(parts) < 2:
            continue
        mnemonic = parts[1].split(" ")[0]
        # VEX-encoded SSE forms (vaddps %xmm...) are AVX too; vzeroupper is AVX.
        if AVX_OPERAND.search(line) or (mnemonic.startswith("v") and "xmm" in line) or mnemonic == "vzeroupper":
            found.add(current)
    return found


# rtrender keeps its symbols; the rtcore module, stripped, has the same library code.
def test_only_the_dispatched_kernels_use_avx(rtrender):
    functions = avx_functions(rtrender)
    for isa in ("avx2", "avx512"):
        assert any(KERNEL.match(f) and f"rt::{isa}::" in f for f in functions), f"the {isa} kernels are in the binary"
    stray = sorted(f for f in functions if not KERNEL.match(f))
    assert not stray, f"AVX code outside the dispatched kernels would crash older CPUs: {stray[:10]}"


def pixels(path):
    return CAP_DATE.sub(b"", path.read_bytes())


def render(rtrender, scene, out, *prefix, env=None):
    result = run(*prefix, rtrender, scene, "-o", out, "--width", 48, "--height", 36, "--quiet", env=env)
    assert result.returncode == 0, result.stderr
    return re.search(r"\((\w+) kernels\)", result.stdout)[1]


def test_every_simd_path_renders_the_same_image(rtrender, scenes_dir, tmp_path):
    native = render(rtrender, scenes_dir / "bunny.glb", tmp_path / "native.exr")
    generic = render(rtrender, scenes_dir / "bunny.glb", tmp_path / "generic.exr", env={"RT_SIMD": "generic"})
    assert generic == "generic"
    assert native in ("generic", "avx2", "avx512")
    assert pixels(tmp_path / "native.exr") == pixels(tmp_path / "generic.exr")


def test_a_cpu_without_avx_runs_the_generic_kernels(rtrender, scenes_dir, tmp_path):
    qemu = shutil.which("qemu-x86_64")
    assert qemu, "qemu-user is missing: `make deps` installs it"
    scene = scenes_dir / "bunny.glb"
    assert render(rtrender, scene, tmp_path / "old.exr", qemu, "-cpu", "Nehalem") == "generic"
    assert render(rtrender, scene, tmp_path / "haswell.exr", qemu, "-cpu", "Haswell") == "avx2"
    render(rtrender, scene, tmp_path / "here.exr")
    here = pixels(tmp_path / "here.exr")
    assert pixels(tmp_path / "old.exr") == here
    assert pixels(tmp_path / "haswell.exr") == here


@pytest.mark.parametrize("value, message", [("sse9", "unknown SIMD path"), ("avx2", None), ("avx512", None)])
def test_a_forced_path_is_checked(rtrender, scenes_dir, tmp_path, value, message):
    qemu = shutil.which("qemu-x86_64")
    assert qemu, "qemu-user is missing: `make deps` installs it"
    prefix = (qemu, "-cpu", "Nehalem")
    result = run(*prefix, rtrender, scenes_dir / "cornell.obj", "-o", tmp_path / "x.png", "--width", 8,
                 "--height", 8, "--quiet", env={"RT_SIMD": value})
    assert result.returncode != 0
    assert (message or "does not support it") in result.stderr
