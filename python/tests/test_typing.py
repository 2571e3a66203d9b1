"""The typed API: the declarations are the built core's (generate_api.py --check); mypy --strict and
pyright (strict) find no error in the README's snippets and in a script calling every public
function, and catch each mistake in typing/typo.py; the runtime signatures say the same."""

import inspect
import json
import os
import pathlib
import re
import subprocess
import sys

import pytest

import panoproj as pp

ROOT = pathlib.Path(__file__).resolve().parents[2]
TYPING = pathlib.Path(__file__).parent / "typing"
PACKAGE_PARENT = str(pathlib.Path(pp.__file__).resolve().parents[1])
INSTALLED = PACKAGE_PARENT.endswith("-packages")  # an installed wheel: the checkers find it themselves


def _env():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    if not INSTALLED:
        env["MYPYPATH"] = PACKAGE_PARENT
    return env


@pytest.fixture(scope="module")
def sources(tmp_path_factory):
    d = tmp_path_factory.mktemp("typing")
    snippets = re.findall(r"```python\n(.*?)```", (ROOT / "python" / "README.md").read_text(), re.S)
    for i, s in enumerate(snippets):
        (d / f"readme_{i}.py").write_text(s)
    for f in ("every_function.py", "typo.py"):
        (d / f).write_text((TYPING / f).read_text())
    (d / "pyrightconfig.json").write_text(json.dumps({"extraPaths": [] if INSTALLED else [PACKAGE_PARENT],
                                                            "typeCheckingMode": "strict"}))
    return d


def _clean(d):
    return sorted(str(p) for p in d.glob("*.py") if p.name != "typo.py")


def test_declarations_are_generated_from_the_built_core():
    r = subprocess.run([sys.executable, str(ROOT / "python" / "generate_api.py"), "--check"], env=_env(),
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_mypy_strict(sources):
    r = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental", *_clean(sources)],
                       cwd=sources, env=_env(), capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout[-3000:]
    r = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental", "typo.py"], cwd=sources,
                       env=_env(), capture_output=True, text=True, timeout=600)
    assert sorted({int(m) for m in re.findall(r"typo\.py:(\d+): error", r.stdout)}) == [7, 8, 9, 10], r.stdout


def test_pyright_strict(sources):
    pyright = [sys.executable, "-m", "pyright", "--pythonpath", sys.executable]
    r = subprocess.run(pyright + _clean(sources), cwd=sources, env=_env(), capture_output=True, text=True, timeout=600)
    assert r.returncode == 0 and re.search(r"^0 errors", r.stdout, re.M), r.stdout[-3000:]
    r = subprocess.run(pyright + ["typo.py"], cwd=sources, env=_env(), capture_output=True, text=True, timeout=600)
    assert sorted({int(m) for m in re.findall(r"typo\.py:(\d+):\d+ - error", r.stdout)}) == [7, 8, 9, 10], r.stdout


def test_every_function_runs():
    r = subprocess.run([sys.executable, str(TYPING / "every_function.py")], cwd=ROOT, env=_env(), capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]


def test_runtime_signatures_list_the_keys():
    for info in pp.projections():
        params = inspect.signature(info.cls).parameters
        assert list(params) == [p.key for p in info.parameters], info.name
        assert all(p.kind is inspect.Parameter.KEYWORD_ONLY and p.default is None for p in params.values())
    assert list(inspect.signature(pp.Fisheye).parameters)[:2] == ["fov", "model"]
    options = [o["name"] for o in pp._core.options() if "convert" in o["use"]]
    assert [p for p in inspect.signature(pp.convert).parameters][3:] == options
    assert [p for p in inspect.signature(pp.Plan).parameters][3:] == options


def test_projections_is_the_catalogue():
    infos = pp.projections()
    assert [i.name for i in infos] == [d["name"] for d in pp._core.catalog()]
    for i in infos:
        assert i.cls.name == i.name and i.cls.summary == i.summary and str(i.cls()) == i.name
        for p in i.parameters:
            if p.choices:  # every choice is accepted, and what is not a choice is not
                for c in p.choices:
                    assert pp.projection(f"{i.name}:{p.key}={c}").params[p.key] == c
                with pytest.raises(ValueError, match=p.key):
                    pp.projection(f"{i.name}:{p.key}=nonsense")
