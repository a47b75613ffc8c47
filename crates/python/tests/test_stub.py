"""The stub fpc.pyi describes the dicts the module returns: every key a
result has is a field of its TypedDict."""

import ast
import pathlib

import pytest

import fpc

STUB = pathlib.Path(__file__).resolve().parents[1] / "fpc.pyi"


def fields(name):
    tree = ast.parse(STUB.read_text())
    for node in tree.body:
        if isinstance(node, ast.ClassDef) and node.name == name:
            return {
                n.target.id
                for n in node.body
                if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)
            }
    pytest.fail(f"no class {name} in fpc.pyi")


def test_a_solve_report_and_its_steps_match_the_stub():
    r = fpc.Finger().solve(pressure_kpa=20)
    assert set(r["report"]) <= fields("Report"), set(r["report"]) - fields("Report")
    steps = r["report"]["steps"]
    assert set(steps) == fields("Steps"), set(steps) ^ fields("Steps")


def test_a_grasp_matches_the_stub():
    g = fpc.Gripper()
    for grasp in (g.grasp_cuboid(), g.grasp_sphere()):
        assert set(grasp) <= fields("Grasp"), set(grasp) - fields("Grasp")
        assert set(grasp["verdict"]) == fields("Verdict")
