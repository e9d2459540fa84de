"""The ESTD vocabulary and its reference documentation stay in step."""

def test_docs_describe_every_controller_and_condition_of_the_vocabulary():
    """docs/estd.md is the reference a factory author reads: nothing in the vocabulary may be missing."""
    from atd.model.controllers import CONDITIONS, CONTROLLERS
    from tests.conftest import REPO

    text = (REPO / "docs" / "estd.md").read_text()
    missing = [name for name in [*CONTROLLERS, *CONDITIONS] if f"### `{name}`" not in text]
    assert missing == []
