#!/usr/bin/env python3
"""Latency of `volstream view`: camera message -> frame received (and JPEG-decoded when PIL is
available), paired with the render time the server reports for the same frame.

    volstream demo jet --cells 1e6 -o /tmp/jet1m -q
    volstream view /tmp/jet1m --port 8089 &
    python3 bench/view_latency.py --port 8089 --frames 40

A minimal RFC 6455 client (no package needed): each camera message orbits a little, the client
waits for that frame before sending the next one (what a user sees when the renderer keeps up).
"""
import argparse
import base64
import json
import math
import os
import socket
import statistics
import struct
import time


class WebSocket:
    def __init__(self, host, port, path="/ws"):
        self.sock = socket.create_connection((host, port))
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET {path} HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n").encode())
        response = b""
        while b"\r\n\r\n" not in response:
            response += self.sock.recv(4096)
        head, self.buffer = response.split(b"\r\n\r\n", 1)
        if b" 101 " not in head.split(b"\r\n")[0]:
            raise RuntimeError("no WebSocket upgrade: " + head.decode(errors="replace"))

    def send_text(self, text):
        payload, mask = text.encode(), os.urandom(4)
        header = bytes([0x81])
        n = len(payload)
        header += bytes([0x80 | n]) if n < 126 else bytes([0x80 | 126]) + struct.pack(">H", n) if n < 65536 \
            else bytes([0x80 | 127]) + struct.pack(">Q", n)
        self.sock.sendall(header + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload)))

    def _read(self, n):
        while len(self.buffer) < n:
            chunk = self.sock.recv(1 << 20)
            if not chunk:
                raise RuntimeError("connection closed")
            self.buffer += chunk
        data, self.buffer = self.buffer[:n], self.buffer[n:]
        return data

    def receive(self):
        """(opcode, payload) of the next message (the server does not fragment)."""
        b0, b1 = self._read(2)
        n = b1 & 0x7F
        if n == 126:
            n = struct.unpack(">H", self._read(2))[0]
        elif n == 127:
            n = struct.unpack(">Q", self._read(8))[0]
        return b0 & 0x0F, self._read(n)


def camera_at(angle, centre, radius, height):
    return {"pos": [centre[0] + radius * math.cos(angle), centre[1] + height, centre[2] + radius * math.sin(angle)],
            "at": centre, "up": [0, 1, 0], "fov": 35}


def orbit(cam, frames):
    """Cameras of `frames` small orbit steps about the first frame's camera (its centre and radius)."""
    offset = [p - a for p, a in zip(cam["pos"], cam["at"])]
    radius, up = math.hypot(offset[0], offset[2]), offset[1]
    base = math.atan2(offset[2], offset[0])
    return [camera_at(base + 0.02 * (i + 1), cam["at"], radius, up) for i in range(frames)]


def print_stats(rows):
    """rows: (name, values in ms) pairs, printed as median, min and max."""
    for name, values in rows:
        print(f"{name}: median {statistics.median(values):.1f} ms, min {min(values):.1f}, max {max(values):.1f}")


def next_frame(ws):
    while True:
        opcode, payload = ws.receive()
        if opcode == 1:
            raise RuntimeError("server error: " + json.loads(payload)["message"])
        if opcode == 2:
            length = struct.unpack("<I", payload[:4])[0]
            return json.loads(payload[4:4 + length]), payload[4 + length:]


def parse_args():
    """The options of both latency scripts: the server, the frame size, how many frames."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--host", default="127.0.0.1")
    ap.add_argument("--port", type=int, default=8080)
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--frames", type=int, default=40)
    args = ap.parse_args()
    width, height = map(int, args.size.split("x"))
    return args, width, height


def main():
    args, width, height = parse_args()
    try:
        from PIL import Image  # noqa: the decode step, as the browser does
        import io
        decode = lambda jpeg: Image.open(io.BytesIO(jpeg)).load()  # noqa: E731
    except ImportError:
        decode = None

    ws = WebSocket(args.host, args.port)
    ws.send_text(json.dumps({"type": "view", "width": width, "height": height, "preview": False}))
    first, _ = next_frame(ws)  # the default view: its camera gives the orbit's centre and radius
    latencies, renders, encodes, sizes = [], [], [], []
    for camera in orbit(first["camera"], args.frames):
        message = {"type": "view", "camera": camera}
        sent = time.perf_counter()
        ws.send_text(json.dumps(message))
        header, jpeg = next_frame(ws)
        if decode:
            decode(jpeg)
        latencies.append((time.perf_counter() - sent) * 1e3)
        renders.append(header["render_ms"])
        encodes.append(header["encode_ms"])
        sizes.append(len(jpeg))
    print(f"{args.frames} frames {width}x{height}, JPEG {statistics.median(sizes) / 1024:.0f} KiB median, "
          f"decode {'PIL' if decode else 'not measured (no PIL)'}")
    print_stats((("latency (message -> frame received%s)" % (" and decoded" if decode else ""), latencies),
                 ("render (server)", renders), ("JPEG encode (server)", encodes)))


if __name__ == "__main__":
    main()
