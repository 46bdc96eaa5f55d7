#!/usr/bin/env python3
"""A tumbled subscriber in Python: prints the lidar pose T_WL from TUMBLE_ODOM
while tumbled says it can be trusted, each state change from TUMBLE_STATUS,
and each re-initialisation (a new local map).

    python3 subscriber.py [--lcm-url URL] [--prefix TUMBLE_] [--poses N] [--timeout-s T] [--types DIR]

Exits 0 after N trusted poses (0, the default: runs until interrupted), 1 when
T seconds pass first.

Debian packages no Python binding of LCM, so this reads LCM's UDP multicast
protocol itself: a datagram holds the magic "LC02", a sequence number, the
channel name and the message. TUMBLE_ODOM and TUMBLE_STATUS always fit one
datagram; larger messages (TUMBLE_SCAN) come in fragments ("LC03"), which this
skips. The messages decode with the classes `lcm-gen --python` writes
(installed in /usr/share/tumble/python). With the lcm module installed, its
lcm.LCM(url).subscribe(channel, handler) replaces the receiver below.
"""
import argparse
import socket
import struct
import sys
import time
import urllib.parse

SHORT_MESSAGE_MAGIC = 0x4C433032  # "LC02"


def open_receiver(url):
    """A socket on the udpm:// URL's group and port (LCM's default, tumbled's too)."""
    parsed = urllib.parse.urlparse(url)
    if parsed.scheme != "udpm":
        sys.exit(f"only udpm:// URLs are read here, not {url}")
    group, port = parsed.hostname or "239.255.76.67", parsed.port or 7667
    receiver = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    receiver.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # beside other LCM subscribers
    receiver.bind(("", port))
    membership = struct.pack("4s4s", socket.inet_aton(group), socket.inet_aton("0.0.0.0"))
    receiver.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP, membership)
    receiver.settimeout(0.1)
    return receiver


def messages(receiver):
    """(channel, payload) of each one-datagram LCM message; None when none came for 0.1 s."""
    while True:
        try:
            datagram = receiver.recv(65536)
        except socket.timeout:
            yield None
            continue
        if len(datagram) < 8 or struct.unpack(">I", datagram[:4])[0] != SHORT_MESSAGE_MAGIC:
            continue
        end = datagram.find(b"\0", 8)
        if end >= 0:
            yield datagram[8:end].decode("utf-8", "replace"), datagram[end + 1:]


class Subscriber:
    def __init__(self, types):
        self.types = types
        self.state = None  # none received yet
        self.resets = None
        self.trusted_poses = 0

    def on_status(self, status):
        if status.state != self.state:
            print(f"state {status.state_name}: {status.state_reason}")
        self.state = status.state

    def on_odometry(self, odometry):
        odometry_t, status_t = self.types.odometry_t, self.types.status_t
        # A new local map: the poses after it do not continue those before.
        if self.resets is not None and odometry.resets != self.resets:
            print(f"re-initialised (resets {odometry.resets}): the trajectory is discontinuous here")
        self.resets = odometry.resets
        trusted = (self.state == status_t.STATE_TRACKING
                   and odometry.flags & odometry_t.FLAG_INITIALISED
                   and not odometry.flags & odometry_t.FLAG_AWAITING_REST)
        if not trusted:
            return
        self.trusted_poses += 1
        p, q = odometry.position_m, odometry.orientation  # q: w, x, y, z of W <- L
        print(f"{odometry.utime * 1e-6:.6f} s  p_W {p[0]:.3f} {p[1]:.3f} {p[2]:.3f} m  "
              f"q_WL (w x y z) {q[0]:.4f} {q[1]:.4f} {q[2]:.4f} {q[3]:.4f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lcm-url", default="udpm://239.255.76.67:7667?ttl=0")
    parser.add_argument("--prefix", default="TUMBLE_")
    parser.add_argument("--poses", type=int, default=0, help="exit 0 after this many trusted poses (0: never)")
    parser.add_argument("--timeout-s", type=float, default=0, help="exit 1 after this long (0: never)")
    parser.add_argument("--types", default="/usr/share/tumble/python", help="where the lcm-gen classes are")
    args = parser.parse_args()

    sys.path.insert(0, args.types)
    import tumble  # the lcm-gen classes

    subscriber = Subscriber(tumble)
    handlers = {args.prefix + "STATUS": (tumble.status_t, subscriber.on_status),
                args.prefix + "ODOM": (tumble.odometry_t, subscriber.on_odometry)}
    receiver = open_receiver(args.lcm_url)
    print("listening", flush=True)
    start = time.monotonic()
    for message in messages(receiver):
        if message is not None and message[0] in handlers:
            message_type, handle = handlers[message[0]]
            handle(message_type.decode(message[1]))
            sys.stdout.flush()
        if args.poses and subscriber.trusted_poses >= args.poses:
            return 0
        if args.timeout_s and time.monotonic() - start > args.timeout_s:
            print(f"{subscriber.trusted_poses} trusted poses in {args.timeout_s:.0f} s, not {args.poses}",
                  file=sys.stderr)
            return 1


if __name__ == "__main__":
    sys.exit(main())
