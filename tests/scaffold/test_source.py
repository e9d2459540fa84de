"""Values from input become Python literals that read back as they were, or are refused:
never code (atd/scaffold/source.py)."""

from __future__ import annotations

import ast
import random

import numpy as np
import pytest

from atd.scaffold.source import SourceError, identifier, literal

HOSTILE = [
    'panda_hand"; open("pwned.txt", "w").write("x"); X = "',
    "a'b", '"""', "'''", 'x\\', "\\n", "line\nbreak", "cr\rlf", "nul\x00byte", "tab\t",
    "{__import__('os').system('true')}", "f'{x}'", "é中🤖", "\u2028\u2029", "\ud800", " ", "",
    "__import__('os')", "x" * 10_000,
]


def _random_text(rng: random.Random) -> str:
    alphabet = "\"'\\\n\r{}()[]#;:=. _aZ0\x00\x7f\u00e9\u2028\U0001f916"
    return "".join(rng.choice(alphabet) for _ in range(rng.randrange(0, 40)))


@pytest.mark.parametrize("text", HOSTILE)
def test_hostile_text_reads_back_as_one_string_expression(text):
    source = literal(text)
    tree = ast.parse(source, mode="eval")
    assert isinstance(tree.body, ast.Constant) and tree.body.value == text


def test_a_seeded_sample_of_nested_values_reads_back_equal_and_of_the_same_types():
    rng = random.Random(30)
    for _ in range(300):
        value = (_random_text(rng), rng.uniform(-1e9, 1e9), rng.randrange(-10**6, 10**6),
                 {_random_text(rng): (_random_text(rng),)}, rng.choice([True, False, None]))
        source = literal(value)
        assert ast.literal_eval(source) == value
        assert source.count("\n") == 0  # one line: it cannot end a comment or a statement early


def test_a_numpy_float_is_written_as_a_plain_number():
    assert literal((np.float64(0.25), 0.5)) == "(0.25, 0.5)"
    assert literal(("one",)) == "('one',)"


@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf"), (1.0, float("nan")), [1, 2],
                                   {1: "a"}, object(), np.int64(3)])
def test_what_no_literal_holds_is_refused(value):
    with pytest.raises(SourceError):
        literal(value)


@pytest.mark.parametrize("name", ["pybullet_data", "_x", "A9"])
def test_a_plain_name_is_kept(name):
    assert identifier(name) == name


@pytest.mark.parametrize("name", ["", "9lives", "a-b", "a.b", "a b", "class", "é", "x\n", "a" * 65,
                                  "__import__('os')"])
def test_anything_else_cannot_be_written_as_a_name(name):
    with pytest.raises(SourceError):
        identifier(name)
