"""What a local pool's forkserver loads before it forks a worker: the trial code, MuJoCo (with
its OpenGL bindings) and the compiled model templates. Loaded there once, every worker starts
with them; each used to load them on its first trial (0.54 G instructions, a tenth of a
trial; docs/campaigns.md). Nothing here builds an engine: no model, no GL context, no thread."""

import atd.campaign.trial  # noqa: F401
import atd.sim.mujoco_engine  # noqa: F401
from atd.sim.models import compile_templates

compile_templates()
