"""The generic translator: ATD in, ESTD out, through one robot's factory (thesis Fig. 7.3).

It knows no robot. It asks the factory about every node, then every edge, enforces the
three translation rules, stamps every ESTD element with the id of the ATD element it came
from, translates sub-tasks recursively, and emits nothing when anything cannot be mapped.
"""

from translator.rules import check_rules
from translator.translate import Translation, translate

__all__ = ["Translation", "check_rules", "translate"]
