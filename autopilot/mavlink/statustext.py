"""STATUSTEXT as ArduPilot sends a text: up to 50 bytes in one message (id 0); a longer text in
50-byte chunks sharing an id (1, 2, ... per sender, 0 skipped) numbered by chunk_seq, the text's
end marked by a chunk shorter than 50 bytes (an empty one when the text fills its last chunk)."""
from __future__ import annotations

CHUNK_BYTES = 50  # STATUSTEXT's text field
TEXT_MAX_BYTES = 256  # ArduPilot's text buffer: longer texts are cut


class StatusTexts:
    def __init__(self, codec) -> None:
        self.codec = codec
        self._last_id = 0

    def encode(self, severity: int, text: str) -> list:
        data = text.encode()[:TEXT_MAX_BYTES]
        if len(data) <= CHUNK_BYTES:
            return [self.codec.statustext_encode(severity, data)]
        self._last_id = self._last_id % 0xFFFF + 1
        chunks = [data[i:i + CHUNK_BYTES] for i in range(0, len(data) + 1, CHUNK_BYTES)]
        if len(chunks[-1]) == 0 and len(data) % CHUNK_BYTES:
            chunks.pop()
        return [self.codec.statustext_encode(severity, chunk, self._last_id, seq) for seq, chunk in enumerate(chunks)]
