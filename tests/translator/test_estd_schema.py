"""schemas/estd.xsd lists exactly the vocabulary of atd/model/controllers.py and vocabulary.EventType."""

from lxml import etree

from atd.model import EventType
from atd.model.controllers import ARM_CONTROLLERS, CONDITIONS, HAND_CONTROLLERS
from schemas import schema_path

XS = "{http://www.w3.org/2001/XMLSchema}"


def _enumeration(name: str) -> set[str]:
    root = etree.parse(str(schema_path("estd.xsd"))).getroot()
    simple = root.find(f"{XS}simpleType[@name='{name}']")
    return {e.get("value") for e in simple.iter(f"{XS}enumeration")}


def test_xsd_names_match_the_vocabulary():
    assert _enumeration("armController") == set(ARM_CONTROLLERS)
    assert _enumeration("handController") == set(HAND_CONTROLLERS)
    assert _enumeration("conditionKind") == set(CONDITIONS)
    assert _enumeration("eventType") == {e.value for e in EventType}
