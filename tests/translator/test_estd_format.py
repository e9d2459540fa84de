"""The ESTD vocabulary and its reference documentation stay in step."""

from atd.model.estd_doc import START, reference
from tests.conftest import REPO


def test_the_reference_a_factory_author_reads_is_the_vocabulary_itself():
    """docs/estd.md's controllers and conditions, parameters and defaults, are those of
    atd/model/controllers.py; after changing the vocabulary, `python -m atd.model.estd_doc`."""
    text = (REPO / "docs" / "estd.md").read_text()
    assert START in text
    assert text[text.index(START):] == reference()
    assert "### `cartesian_move` (thesis 3.3.2" in reference() and "| `target` | vector | required | m |" in reference()
