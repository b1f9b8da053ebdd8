"""The attribute allowlist and the size/work limits on what numpy and the builtins hand out."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pytest

from voxposer.errors import ConfigError, SandboxError
from voxposer.lmp.object_view import ObjectView
from voxposer.lmp.sandbox import Sandbox, SandboxConfig


@pytest.fixture(scope="module", params=["inline", "process"])
def small(request: pytest.FixtureRequest) -> Sandbox:
    """Tight limits, so that every refusal below is cheap to provoke (in both modes)."""
    sandbox = Sandbox(SandboxConfig(time_limit_s=5.0, max_elements=100_000, max_work=1_000_000,
                                    isolation=request.param))
    yield sandbox
    sandbox.close()


def _object() -> ObjectView:
    return ObjectView("blue block", np.array([1, 2, 3]), np.zeros((2, 3), int),
                      np.zeros((4, 4, 4), bool), np.array([0.0, 0.0, 1.0]), np.zeros(3),
                      np.zeros((2, 3)))


def test_the_issue_example_is_refused_before_it_allocates() -> None:
    with pytest.raises(SandboxError, match=r"size limit: ndarray\.repeat would create 1e\+08"):
        Sandbox().run("a = np.zeros(1000).repeat(10**5)", {})


NOT_ON_THE_LIST = {
    "x = np.zeros(4).view('int8')": ".view",
    "x = np.zeros(3).flags": ".flags",
    "x = np.zeros(3).base": ".base",
    "x = np.zeros(3).tobytes()": ".tobytes",
    "np.zeros(3).put(-1, 5)": ".put",
    "x = np.zeros(3).flat": ".flat",
    "x = np.float64(1.0).setflags": ".setflags",
    "x = (1).to_bytes(10, 'big')": ".to_bytes",
    "x = np.add.at": ".at",
    "x = np.linalg.norm.x": ".x",
    "x = np.float64.mro": ".mro",
    "x = Rotation.from_quat([0, 0, 0, 1]).x": ".x",
    "x = Rotation.create_group": ".create_group",
    "x = (lambda: 1).x": ".x",
    "x = map(abs, [1]).x": ".x",
    "x = np.random.default_rng(0).bit_generator": ".bit_generator",
    "x = np.random.default_rng(0).spawn(10**9)": ".spawn",
    "x = obj.from_detection": ".from_detection",
}


@pytest.mark.parametrize("code, attr", list(NOT_ON_THE_LIST.items()))
def test_attributes_off_the_list_are_refused_by_name(small: Sandbox, code: str, attr: str
                                                     ) -> None:
    with pytest.raises(SandboxError, match=rf"refused: .*`\{attr}`"):
        small.run(code, {"obj": _object()})


def test_the_refusal_lists_what_is_allowed(small: Sandbox) -> None:
    with pytest.raises(SandboxError) as info:
        small.run("x = np.zeros(3).view('int8')", {})
    assert "allowed:" in str(info.value)
    assert all(name in str(info.value) for name in ("astype", "reshape", "sum", "shape"))
    with pytest.raises(SandboxError, match=r"data attributes .*position"):
        small.run("x = obj.from_detection", {"obj": _object()})


ALLOCATING = [
    "a = np.zeros(1000).repeat(1000)",
    "a = np.float64(1.0).repeat(10**6)",
    "a = np.zeros(10)\na.resize((1000, 1000))",
    "a = np.zeros((2, 1000)).take(np.zeros(1000, int), axis=0)",
    "a = np.ones((40, 40, 40)).nonzero()",
    "a = np.add.outer(np.arange(1000), np.arange(1000))",
    "a = np.add.reduce([np.zeros(60_000), np.zeros(60_000)])",
    "a = Rotation.random(10**5)",
    "a = np.random.default_rng(0).random(10**6)",
    "a = np.random.default_rng(0).normal(0, 1, (1000, 1000))",
    "a = np.random.rand(1000, 1000)",
    "a = ''.join(['x' * 1000] * 1000)",
    "a = ('a' * 1000).replace('a', 'b' * 400)",
    "a = [0] * 1000\nfor i in range(10):\n    a.extend(a)",
    "a = [0] * 1000\nfor i in range(10):\n    a = a + a",
    "a = sum([[0] * 1000] * 1000, [])",
    "a = '%*d' % (10**6, 1)",
    "a = '%.1000000f' % 1.0",
    "a = f'{1:>1000000}'",
    "a = np.r_[0:10**6]",
    "a = np.multiply(np.arange(1000)[:, None], np.arange(1000))",
    "a = np.concatenate([np.zeros(60_000)] * 2)",
    "a = np.array([np.zeros(60_000)] * 2)",
    "a = np.diag(np.zeros(1000))",
    "a = np.bincount([10**6])",
    "a = np.ones((1000, 1)) @ np.ones((1, 1000))",
    "a = np.matmul(np.ones((1000, 2)), np.ones((2, 1000)))",
    "a = np.ones((1000, 2)).dot(np.ones((2, 1000)))",
    "a = np.linalg.svd(np.ones((1000, 3)))",
    "a = np.zeros((2, 1000))[np.zeros(1000, int)]",
]


@pytest.mark.parametrize("code", ALLOCATING)
def test_allocating_methods_and_calls_are_size_checked(small: Sandbox, code: str) -> None:
    with pytest.raises(SandboxError, match="size limit"):
        small.run(code, {})


SUPER_LINEAR = {
    "a = np.ones((200, 200)) @ np.ones((200, 200))": "a @ b",
    "a = np.ones((200, 200)).dot(np.ones((200, 200)))": "ndarray.dot",
    "a = np.dot(np.ones((200, 200)), np.ones((200, 200)))": "np.dot",
    "a = np.matmul(np.ones((200, 200)), np.ones((200, 200)))": "np.matmul",
    "a = np.einsum('ij,jk->ik', np.ones((200, 200)), np.ones((200, 200)))": "np.einsum",
    "a = np.linalg.inv(np.eye(200))": "np.linalg.inv",
    "a = np.linalg.solve(np.eye(200), np.ones(200))": "np.linalg.solve",
    "a = np.linalg.eigh(np.eye(200))": "np.linalg.eigh",
    "a = np.linalg.norm(np.ones((200, 200)), 2)": "np.linalg.norm",
    "a = np.sort(np.ones(10**5))": "np.sort",
    "a = np.unique(np.arange(10**5))": "np.unique",
    "a = np.ones(10**5).argsort()": "ndarray.argsort",
    "a = np.ones(10**5)\na.sort()": "ndarray.sort",
    "a = sorted(range(10**5))": "sorted",
    "a = list(range(10**5))\na.sort()": "list.sort",
    "a = np.convolve(np.ones(2000), np.ones(1000))": "np.convolve",
}


@pytest.mark.parametrize("code, what", list(SUPER_LINEAR.items()))
def test_super_linear_operations_hit_the_work_limit(small: Sandbox, code: str, what: str
                                                    ) -> None:
    with pytest.raises(SandboxError, match=rf"work limit: .*{what.replace('.', '[.]')}"):
        small.run(code, {})


def test_small_versions_of_the_same_calls_run(small: Sandbox) -> None:
    code = (
        "a = np.zeros(10).repeat(3)\n"
        "b = np.arange(12).reshape(3, 4).astype(float).T.copy().ravel()\n"
        "c = np.ones((20, 20)) @ np.ones((20, 20))\n"
        "d = np.linalg.inv(np.eye(20)).dot(np.ones(20))\n"
        "e = np.sort(np.arange(100)[::-1])\n"
        "f = np.linalg.norm(np.ones((200, 200)))\n"  # Frobenius: linear, not checked
        "g = np.add.outer(np.arange(3), np.arange(2)).cumsum()\n"
        "h = ''.join(sorted(['b', 'a'])).upper().replace('A', 'x')\n"
        "k = sum([[1], [2, 3]], [])\n"
        "q = Rotation.from_euler('z', 90, degrees=True).as_quat()\n"
        "r = np.random.default_rng(0).integers(0, 10**9, size=3)\n"
        "s = np.random.randint(0, 10**9, size=3)\n"
        "t = np.finfo(float).eps > 0 and np.zeros(2).dtype.name == 'float64'\n"
        "u = np.maximum(10**8, 5) + np.linalg.norm([3000, 4000, 0])\n"
        "v = obj.position.tolist() + [obj['name'], obj.get('name')]\n"
    )
    out = small.run(code, {"obj": _object()})
    assert out["a"].shape == (30,) and out["b"].shape == (12,)
    assert out["c"][0, 0] == 20 and np.allclose(out["d"], 1) and out["e"][0] == 0
    assert out["g"].tolist() == [0, 1, 2, 4, 6, 9] and out["h"] == "xB"
    assert out["k"] == [1, 2, 3] and out["t"] and out["u"] == 10**8 + 5000
    assert out["v"] == [1, 2, 3, "blue block", "blue block"]


def test_value_map_code_on_a_full_grid_runs_with_the_default_limits() -> None:
    code = (
        "m = np.zeros((100, 100, 100))\n"
        "idx = np.argwhere(m == 0)\n"  # every voxel, shape (1e6, 3)
        "d = np.linalg.norm(idx - np.array([50, 50, 50]), axis=1)\n"
        "order = np.argsort(d)\n"
        "turned = idx @ np.eye(3)\n"
        "m[tuple(idx[order[:10]].T)] = 1\n"
        "near = np.sort(d)[:5]\n"
        "ret_val = float(m.sum())\n"
    )
    out = Sandbox().run(code, {})
    assert out["ret_val"] == 10.0 and out["turned"].shape == (1_000_000, 3)


class Detected(NamedTuple):
    name: str
    position: np.ndarray


def test_a_callers_named_tuple_exposes_its_fields_not_its_methods(small: Sandbox) -> None:
    thing = Detected("pink block", np.array([0.1, 0.2, 0.0]))
    out = small.run("p = thing.position + np.array([0.0, 0.0, 0.1])\nn = thing.name.upper()",
                    {"thing": thing})
    assert np.allclose(out["p"], [0.1, 0.2, 0.1]) and out["n"] == "PINK BLOCK"
    with pytest.raises(SandboxError, match=r"`\.count` of Detected is a method.*name, position"):
        small.run("c = thing.count", {"thing": thing})


def test_allocating_classes_are_size_checked_and_isinstance_still_works(small: Sandbox) -> None:
    with pytest.raises(SandboxError, match=r"size limit: np\.ndarray"):
        small.run("a = np.ndarray((1000, 1000))", {})
    for code in ("a = np.zeros(np.array([1000, 1000]))",
                 "a = np.zeros(10)\na.resize(np.array([1000, 1000]))",
                 "a = np.histogram(np.zeros(3), bins=10**6)",
                 "a = np.fromfunction(lambda i, j: i, (1000, 1000))"):
        with pytest.raises(SandboxError, match="size limit"):
            small.run(code, {})
    out = small.run("ok = isinstance(np.zeros(3), np.ndarray) and not isinstance([], "
                    "(np.ndarray, dict))\nshape = np.ndarray((2, 3)).shape", {})
    assert out["ok"] and out["shape"] == (2, 3)


def test_ints_that_are_data_are_not_taken_for_shapes(small: Sandbox) -> None:
    out = small.run("top = np.max([90, 95, 99, 80, 70])\n"
                    "q = np.percentile(np.arange(10), [1, 5, 10, 25, 50, 75, 90, 95, 99])\n"
                    "p = np.array([500, 600, 700])", {})
    assert out["top"] == 99 and out["q"].shape == (9,) and out["p"].tolist() == [500, 600, 700]


def test_attribute_assignment_is_refused_naming_the_attribute(small: Sandbox) -> None:
    with pytest.raises(SandboxError, match=r"`\.shape`"):
        small.run("a = np.zeros(4)\na.shape = (2, 2)", {})
    with pytest.raises(SandboxError, match=r"`\.flags`"):
        small.run("a = obj.position\na.flags.writeable = True", {"obj": _object()})


def test_computed_f_string_widths_are_refused(small: Sandbox) -> None:
    with pytest.raises(SandboxError, match="computed format spec"):
        small.run("n = 10**9\na = f'{1:>{n}}'", {})
    out = small.run("a = f'{3.14159:.2f}|{7:>4}|{\"b\"!r}' + '%5.1f %s %%' % (2.25, 'x')", {})
    assert out["a"] == "3.14|   7|'b'  2.2 x %"


def test_two_argument_iter_is_refused(small: Sandbox) -> None:
    with pytest.raises(SandboxError, match=r"iter\(callable, sentinel\)"):
        small.run("x = list(iter(int, 1))", {})


def test_max_work_is_validated() -> None:
    assert SandboxConfig().max_work == 1_000_000_000
    for bad in (10, 1.5e9, True, "1e9"):
        with pytest.raises(ConfigError, match=rf"max_work .*{bad!r}"):
            SandboxConfig(max_work=bad)  # type: ignore[arg-type]
