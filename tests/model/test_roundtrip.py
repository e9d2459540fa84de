"""parse -> write -> parse gives an equal model, and what we write passes our own checks."""

from hypothesis import HealthCheck, given, settings

from atd.model import Severity, load_task, task_to_xml
from atd.model.load import _atd_schema
from lxml import etree
from tests.conftest import EXAMPLES, SEEDS
from tests.model.strategies import tasks


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(task=tasks())
def test_write_then_read_gives_the_same_task(task, tmp_path):
    path = tmp_path / "t.xml"
    path.write_bytes(task_to_xml(task))
    again, found = load_task(path)
    assert again == task
    assert not [d for d in found if d.severity is Severity.ERROR], [d.render() for d in found]
    path.write_bytes(task_to_xml(again))
    assert load_task(path)[0] == task


def test_seeds_and_examples_survive_a_round_trip(tmp_path):
    for source in [*SEEDS.glob("*.xml"), *EXAMPLES.glob("*.xml")]:
        task, _ = load_task(source)
        copy = tmp_path / source.name
        copy.write_bytes(task_to_xml(task))
        assert load_task(copy)[0] == task, source.name


@settings(max_examples=60, deadline=None)
@given(task=tasks())
def test_written_files_satisfy_the_xsd(task):
    assert _atd_schema().validate(etree.fromstring(task_to_xml(task)))
