"""The process that writes a recording: it takes sample rows from the control loop through
a pipe, turns them into JSON messages and MCAP records on the other core, and writes the
file whole when told the run ended. If the feed ends without that word (the run raised,
was stopped with Ctrl-C, or its engine crashed) it writes nothing, so a recording, like
every other output, is either complete or absent.

It is forked, not spawned: it starts in milliseconds with every module loaded. It touches
no engine (it only encodes numbers and writes bytes), so forking beside a live engine is
safe; it freezes what it inherited from the garbage collector, so no engine object copied
into it is ever finalised there.
"""

from __future__ import annotations

import fcntl
import gc
import io
import itertools
import json
import os
import pickle
import signal
import time
from pathlib import Path
from typing import Any, BinaryIO, Iterator, NoReturn

from mcap.writer import CompressionType, Writer

from atd.model.files import OutputError, write_output
from atd.runtime import recording_images, recording_scene
from atd.runtime.recording_format import CHANNELS, CLOCK, PROFILE, Layout, encode, messages, schemas_of
from atd.runtime.recording_scene import SceneWriter

WRITTEN = "written"  # the writer's answer when the file is
PIPE_SIZE = 1 << 20  # bytes: about 20 blocks, 5 s of a run recorded at 100 Hz (Linux's default limit)


class RecordingWriter:
    """The control loop's end of the writer process: `send` feeds it, `finish` has it write
    the file, `abandon` has it end without writing."""

    def __init__(self, path: Path) -> None:
        feed_out, feed_in = os.pipe()
        _widen(feed_in)
        answer_out, answer_in = os.pipe()
        signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})  # none may land before the child ignores it
        pid = os.fork()
        if pid == 0:
            os.close(feed_in)
            os.close(answer_out)
            signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C stops the run, which tells this process
            signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
            _serve(path, os.fdopen(feed_out, "rb"), answer_in)
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
        os.close(feed_out)
        os.close(answer_in)
        self.path, self.answer = path, answer_out
        self.pid: int | None = pid
        self.feed: BinaryIO | None = os.fdopen(feed_in, "wb")

    def send(self, item: tuple) -> None:
        """Pass `item` on; a writer that has already ended is heard of at `finish`."""
        if self.feed is None:
            return
        try:
            pickle.dump(item, self.feed, protocol=pickle.HIGHEST_PROTOCOL)
        except BrokenPipeError:
            self._close_feed()

    def finish(self, outcome: dict[str, str]) -> None:
        """Have the file written; OutputError when it could not be."""
        self.send(("end", outcome))
        self._close_feed()
        with os.fdopen(self.answer, "rb") as answer:
            said = answer.read().decode()
        self._reap()
        if said != WRITTEN:
            raise OutputError(said or f"cannot write {self.path}: the recording's writer process ended early")

    def abandon(self) -> None:
        """End the writer without a file (the run did not end); after `finish`, nothing."""
        if self.pid is None:
            return
        self._close_feed()
        os.close(self.answer)
        self._reap()

    def _reap(self) -> None:
        os.waitpid(self.pid, 0)
        self.pid = None

    def _close_feed(self) -> None:
        if self.feed is not None:
            feed, self.feed = self.feed, None
            try:
                feed.close()
            except BrokenPipeError:
                pass  # what was still buffered is lost with the writer; `finish` says so


def _widen(pipe: int) -> None:
    """Let the pipe hold seconds of samples, not one block: on a busy machine the writer is
    not always scheduled when a block comes, and the control loop should not wait for it."""
    try:
        fcntl.fcntl(pipe, fcntl.F_SETPIPE_SZ, PIPE_SIZE)
    except (AttributeError, OSError):
        pass  # not Linux, or a lower limit set for this system: the pipe keeps its own size


def _serve(path: Path, feed: BinaryIO, answer: int) -> NoReturn:
    """The writer process: read the feed to its end, write the file if the run ended, and
    answer what went wrong (WRITTEN when nothing did). It never returns into the caller's code."""
    try:
        gc.freeze()
        try:
            problem = _write(path, feed)
        except OutputError as exc:
            problem = str(exc)
        except Exception as exc:  # noqa: BLE001 - whatever it is, the run's process must hear of it
            problem = f"cannot write {path}: the recording's writer failed ({type(exc).__name__}: {exc})"
        if problem is not None:
            os.write(answer, (problem or WRITTEN).encode())
    finally:
        os._exit(0)


def _write(path: Path, feed: BinaryIO) -> str | None:
    """The feed's messages, into `path` when it ends with the word "end" (then ""); None
    when it ends without it."""
    buffer = io.BytesIO()
    writer = Writer(buffer, compression=CompressionType.ZSTD)
    writer.start(profile=PROFILE, library="atd")
    channels: dict[str, int] = {}
    layout: Layout | None = None
    scene: SceneWriter | None = None
    sequence = 0
    zero = 0  # ns: the wall clock when the run started (its "start" item), so a viewer shows when it ran

    def add(found: Iterator[tuple[str, int, dict[str, Any]]]) -> None:
        nonlocal sequence
        for topic, ns, message in found:
            sequence += 1
            writer.add_message(channels[topic], zero + ns, encode(message), zero + ns, sequence)

    while True:
        try:
            item: tuple[Any, ...] = pickle.load(feed)
        except (EOFError, pickle.UnpicklingError):
            return None
        if item[0] == "start":
            _, layout, meta, info, attachments = item
            zero = time.time_ns()
            channels = _start(writer, layout, meta, {**info, CLOCK: str(zero)}, attachments)
        elif item[0] == "scene":
            scene = SceneWriter(item[1], zero)
            channels |= _register(writer, recording_scene.SCHEMAS, recording_scene.CHANNELS, {})
        elif item[0] == "image":
            if recording_images.DEPTH not in channels:
                channels |= _register(writer, recording_images.SCHEMAS, recording_images.CHANNELS, {})
            add(recording_images.image_messages(item[1], zero))
        elif item[0] == "rows":
            assert layout is not None, "the feed starts with the layout"
            found = messages(layout, *item[1:])
            if scene is not None:
                found = itertools.chain(found, _drawn(scene, layout, item[1]))
            add(found)
        else:
            writer.add_metadata("atd.outcome", item[1])
            writer.finish()
            write_output(path, buffer.getvalue())
            return ""


def _drawn(scene: SceneWriter, layout: Layout, block: Any) -> Iterator[tuple[str, int, dict[str, Any]]]:
    """The 3D scene's messages due in a block of rows."""
    f = layout.fields
    for row in block:
        yield from scene.messages(float(row[0]), row[f["true_joints"]], row[f["objects"]], row[f["tcp"]].reshape(4, 4))


def _register(writer: Writer, schemas: dict[str, dict[str, Any]], topics: tuple[tuple[str, str, bool], ...],
              meta: dict[str, str]) -> dict[str, int]:
    """JSON `schemas` and the channels of `topics` (each with `ground_truth`, /sensors with
    `meta`); the channel id of each topic."""
    schema_ids = {name: writer.register_schema(name, "jsonschema", json.dumps(schema).encode())
                  for name, schema in schemas.items()}
    channels = {}
    for topic, schema, truth in topics:
        metadata = {"ground_truth": "true" if truth else "false", **(meta if topic == "/sensors" else {})}
        channels[topic] = writer.register_channel(topic, "json", schema_ids[schema], metadata)
    return channels


def _start(writer: Writer, layout: Layout, meta: dict[str, str], info: dict[str, str],
           attachments: dict[str, bytes]) -> dict[str, int]:
    """This robot's schemas, channels (each with `ground_truth`, /sensors with `meta`), the run's metadata
    and attachments; the channel id of each topic."""
    channels = _register(writer, schemas_of(layout), CHANNELS, meta)
    for name, data in info.items():
        writer.add_metadata(name, {"value": data})
    for name, data in attachments.items():
        writer.add_attachment(0, 0, name, "application/xml", data)
    return channels
