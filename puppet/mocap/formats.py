"""The live formats by name, and the ``udp://HOST:PORT`` addresses they come to."""

from __future__ import annotations

import ipaddress

from puppet.data.errors import UsageError
from puppet.mocap.mediapipe import MediaPipeDecoder
from puppet.mocap.mediapipe_bridge import MediaPipeBridgeDecoder
from puppet.mocap.osc import Decoder
from puppet.mocap.puppet_osc import PuppetDecoder
from puppet.mocap.vmc import VmcDecoder

DECODERS: dict[str, type[Decoder]] = {"vmc": VmcDecoder, "mediapipe": MediaPipeDecoder,
                                      "mediapipe-osc": MediaPipeBridgeDecoder,
                                      "puppet": PuppetDecoder}
FORMATS = tuple(DECODERS)
LOCALHOST = "127.0.0.1"


def decoder(name: str) -> Decoder:
    try:
        return DECODERS[name]()
    except KeyError:
        raise UsageError(f"unknown mocap format '{name}'; expected one of: "
                         f"{', '.join(FORMATS)}") from None


def parse_udp(option: str, url: str, default_port: int | None = None,
              default_host: str = LOCALHOST, listening: bool = False) -> tuple[str, int]:
    """``udp://HOST:PORT`` (or ``udp://:PORT``, ``HOST:PORT``, ``:PORT``) as (host, port).
    The host is an IP address (names are not looked up); a usage error says what is
    wrong otherwise. ``listening``: port 0 is allowed (the system picks one)."""
    rest = url[len("udp://"):] if url.startswith("udp://") else url
    if "://" in rest:
        raise UsageError(f"{option} {url}: only udp:// is supported (e.g. "
                         f"udp://127.0.0.1:39539)")
    host, sep, port_text = rest.rpartition(":")
    if not sep:
        host, port_text = rest, ""
    host = host.strip("[]") or default_host
    try:
        ipaddress.ip_address(host)
    except ValueError:
        raise UsageError(f"{option} {url}: '{host}' is not an IP address (e.g. "
                         f"udp://127.0.0.1:39539)") from None
    if not port_text:
        if default_port is None:
            raise UsageError(f"{option} {url}: no port; expected udp://HOST:PORT")
        return host, default_port
    low = 0 if listening else 1
    if not port_text.isdigit() or not low <= int(port_text) <= 65535:
        raise UsageError(f"{option} {url}: the port must be a whole number {low}..65535")
    return host, int(port_text)
