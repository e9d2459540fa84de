"""The records of an MCAP file, read with bounded work whatever its bytes say.

mcap's own reader trusts a chunk: it decompresses whatever a zstd frame declares (a 65 KB
file of 2 GiB of zeros held `atd report` for minutes) and an lz4 chunk without any limit,
then walks zero bytes as millions of empty records. Here every record is checked to lie
within its file or chunk, every chunk before it is opened (its declared size against a
cap, the whole file's against a multiple of the file's own size), opened no further than it
declares and checked against its checksum; a chunk may hold only what MCAP puts in one. A
file that is cut short, or is not MCAP at all, is `Damaged`, with the reason in words.
mcap's record classes still parse each record's fields.
"""

from __future__ import annotations

import io
import struct
import zlib
from typing import BinaryIO, Iterator

import lz4.frame
import zstandard
from mcap.data_stream import ReadDataStream
from mcap.exceptions import EndOfFile, McapError
from mcap.opcode import Opcode
from mcap.records import Attachment, Channel, Chunk, McapRecord, Message, Metadata, Schema
from mcap.writer import MCAP0_MAGIC

MiB = 1 << 20
CHUNK_CAP = 64 * MiB  # bytes a chunk may hold decompressed: `atd run --record` writes chunks of 1 MiB
RECORD_CAP = 64 * MiB  # bytes of a record outside chunks: an attachment holds a task file of at most 32 MiB
INFLATION = 100  # times its own size a whole file may decompress to: recordings measure 9-18 times
INFLATION_FLOOR = 16 * MiB  # what even a small file may decompress to
_HEAD = struct.Struct("<BQ")  # a record's opcode and length
_MESSAGE = struct.Struct("<HIQQ")  # a message's channel id, sequence, log time and publish time
_IN_CHUNK = {Opcode.SCHEMA: Schema.read, Opcode.CHANNEL: Channel.read}
_READ = {**_IN_CHUNK, Opcode.METADATA: Metadata.read, Opcode.ATTACHMENT: Attachment.read}  # and chunks, messages
# What else the file holds (its header, indexes, statistics, the summary) nothing here needs.


class Damaged(McapError):
    """Not an MCAP file, or one that is cut short, damaged or built to exhaust a reader."""


def records(data: bytes) -> Iterator[McapRecord]:
    """The schemas, channels, messages, metadata and attachments of the MCAP file `data`,
    in file order, each chunk's in its place; up to the footer."""
    if not data.startswith(MCAP0_MAGIC):
        raise Damaged("it does not begin with MCAP's magic bytes")
    budget = max(INFLATION_FLOOR, INFLATION * len(data))
    for opcode, start, end in _walk(data, len(MCAP0_MAGIC), "the file"):
        if end - start > RECORD_CAP:
            raise Damaged(f"the record at byte {start - _HEAD.size} is {(end - start) / MiB:.0f} MiB long, more than "
                          f"the {RECORD_CAP // MiB} MiB a record may be")
        if opcode == Opcode.FOOTER:
            if data[end:end + len(MCAP0_MAGIC)] != MCAP0_MAGIC:
                raise Damaged("it ends without MCAP's closing magic bytes: the file was cut short")
            return
        if opcode == Opcode.CHUNK:
            chunk = _parsed(Chunk.read, data, start, end, f"the chunk at byte {start - _HEAD.size}")
            budget -= chunk.uncompressed_size
            yield from _opened(chunk, start - _HEAD.size, budget, len(data))
        elif opcode == Opcode.MESSAGE:
            yield _message(data, start, end, f"the record at byte {start - _HEAD.size}")
        elif opcode in _READ:
            yield _parsed(_READ[opcode], data, start, end, f"the record at byte {start - _HEAD.size}")
    raise Damaged("it ends without MCAP's footer: the file was cut short")


def _walk(data: bytes, at: int, where: str) -> Iterator[tuple[int, int, int]]:
    """(opcode, start, end) of each record from byte `at`, checked to end within `data`."""
    while at < len(data):
        if at + _HEAD.size > len(data):
            raise Damaged(f"{where} ends in the middle of a record at byte {at}: it was cut short")
        opcode, length = _HEAD.unpack_from(data, at)
        start = at + _HEAD.size
        if length > len(data) - start:
            raise Damaged(f"the record at byte {at} of {where} runs past its end: it was cut short")
        yield opcode, start, start + length
        at = start + length


def _parsed(read, data: bytes, start: int, end: int, what: str) -> McapRecord:
    """A record's fields, read by mcap's own class."""
    try:
        return read(ReadDataStream(io.BytesIO(data[start:end])))
    except (EndOfFile, struct.error, ValueError) as exc:  # a field past the record's end, text not UTF-8
        raise Damaged(f"{what} is damaged ({exc or 'a field runs past its end'})") from None


def _message(data: bytes, start: int, end: int, what: str) -> Message:
    """A message, its fixed fields unpacked in one step: a chunk holds a thousand of them."""
    if end - start < _MESSAGE.size:
        raise Damaged(f"{what} is a message of {end - start} bytes, too short to be one")
    channel, sequence, log_time, publish_time = _MESSAGE.unpack_from(data, start)
    return Message(channel_id=channel, sequence=sequence, log_time=log_time, publish_time=publish_time,
                   data=data[start + _MESSAGE.size:end])


def _opened(chunk: Chunk, at: int, budget: int, size: int) -> Iterator[McapRecord]:
    """The schemas, channels and messages of a chunk; anything else there is damage."""
    where = f"the chunk at byte {at}"
    if chunk.uncompressed_size > CHUNK_CAP:
        raise Damaged(f"{where} declares {chunk.uncompressed_size / MiB:.0f} MiB of data, more than the "
                      f"{CHUNK_CAP // MiB} MiB a chunk may hold")
    if budget < 0:
        most = max(INFLATION_FLOOR, INFLATION * size) // MiB
        raise Damaged(f"{where} takes what the file decompresses to past {most} MiB, {INFLATION} times its size: "
                      f"a compression bomb, or a damaged file")
    data = _decompressed(chunk, where)
    if chunk.uncompressed_crc and zlib.crc32(data) != chunk.uncompressed_crc:
        raise Damaged(f"{where} fails its checksum: the file is damaged")
    for opcode, start, end in _walk(data, 0, where):
        if opcode == Opcode.MESSAGE:
            yield _message(data, start, end, f"a record of {where}")
        elif opcode in _IN_CHUNK:
            yield _parsed(_IN_CHUNK[opcode], data, start, end, f"a record of {where}")
        else:  # even an application's own: millions of empty ones would cost seconds to skip
            raise Damaged(f"{where} holds a record of opcode {opcode:#04x}, where MCAP puts only schemas, "
                          f"channels and messages: the file is damaged")


def _decompressed(chunk: Chunk, where: str) -> bytes:
    """The chunk's data, decompressed no further than one byte past what it declares."""
    if chunk.compression == "":
        data = chunk.data
    else:
        try:
            if chunk.compression == "zstd":
                data = _read_at_most(zstandard.ZstdDecompressor().stream_reader(chunk.data),
                                     chunk.uncompressed_size + 1)
            elif chunk.compression == "lz4":
                data = _read_at_most(lz4.frame.LZ4FrameFile(io.BytesIO(chunk.data)), chunk.uncompressed_size + 1)
            else:
                raise Damaged(f"{where} is compressed with {chunk.compression[:40]!r}; MCAP knows zstd and lz4")
        except (zstandard.ZstdError, RuntimeError, EOFError, OSError) as exc:
            raise Damaged(f"{where} cannot be decompressed ({exc}): the file is damaged") from None
    if len(data) != chunk.uncompressed_size:
        raise Damaged(f"{where} declares {chunk.uncompressed_size} bytes of data and holds "
                      f"{'more' if len(data) > chunk.uncompressed_size else len(data)}: the file is damaged")
    return data


def _read_at_most(stream: BinaryIO, limit: int) -> bytes:
    parts, got = [], 0
    while got < limit:
        part = stream.read(limit - got)
        if not part:
            break
        parts.append(part)
        got += len(part)
    return b"".join(parts)
