"""The XSD, the Python vocabulary and the reader agree on what an ATD is."""

import json

import pytest
from click.testing import CliRunner
from lxml import etree

from atd.cli import main
from atd.model.load import _atd_schema
from atd.model.vocabulary import EventType, HandShape, Movement, ObjectClass, StateType
from schemas import schema_path
from tests.model.test_diagnostics import CASES

XS = "{http://www.w3.org/2001/XMLSchema}"


def xsd_enumeration(type_name: str) -> set[str]:
    tree = etree.parse(str(schema_path("atd.xsd")))
    node = tree.find(f"{XS}simpleType[@name='{type_name}']")
    return {e.get("value") for e in node.iter(f"{XS}enumeration")}


@pytest.mark.parametrize("type_name,enum", [
    ("stateType", StateType), ("movement", Movement), ("handShape", HandShape), ("objectClass", ObjectClass)])
def test_xsd_lists_the_same_words_as_the_vocabulary(type_name, enum):
    assert xsd_enumeration(type_name) == {e.value for e in enum}


def test_xsd_events_are_the_vocabulary_events():
    tree = etree.parse(str(schema_path("atd.xsd")))
    transition = tree.find(f"{XS}complexType[@name='transition']")
    assert {e.get("name") for e in transition.iter(f"{XS}element")} == {e.value for e in EventType}


# XSD 1.0 cannot say these; the reader alone checks them.
BEYOND_XSD = {"non-rigid pose", "repeated property", "size count for a cylinder", "task state without file"}
STRUCTURAL = [name for name, (code, _) in CASES.items() if code.startswith("ATD1") and name not in BEYOND_XSD]


@pytest.mark.parametrize("case", STRUCTURAL)
def test_the_xsd_also_refuses_what_the_reader_refuses(case):
    """The XSD is the published contract: files our reader rejects for their structure fail it too."""
    _, xml = CASES[case]
    assert not _atd_schema().validate(etree.fromstring(xml.encode()))


def test_atd_schema_prints_a_json_schema_of_the_model():
    result = CliRunner().invoke(main, ["schema"])
    schema = json.loads(result.output)
    assert result.exit_code == 0
    assert set(schema["properties"]) >= {"states", "transitions", "known_objects", "environment", "initial", "inputs"}
    assert schema["$defs"]["HandShape"]["enum"] == [h.value for h in HandShape]
