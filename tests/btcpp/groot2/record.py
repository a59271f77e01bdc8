#!/usr/bin/env python3
"""Questions BehaviorTree.CPP's Groot2Publisher as Groot2 does and records every reply.

    record.py PUBLISHER TREE.xml PORT > session.txt

PUBLISHER is the program of publisher.cpp. A libzmq REQ socket (pyzmq) sends the
requests Groot2 sends, read from BehaviorTree.CPP 4.10's groot2_publisher.cpp and
groot2_protocol.h (Groot2 itself is not open): the tree, the hooks, recording on, then
after every tick the statuses, and every third tick the transitions recorded; the
blackboards; recording off; and requests a bad client sends. The request ids count
from 1, so that the recording is the same every time but for the tree's UUID and the
times.

The output, one line per event:
    tick N STATUS              the program ticked the tree (BehaviorTree.CPP's status)
    change UID PREV NEW        a status change that tick made, in order
    request NAME HEX[;HEX...]  the parts sent, in hex
    reply HEX[;HEX...]         the parts of the reply
"""
import subprocess
import sys

import zmq

TICKS = 14


def main():
    program, tree, port = sys.argv[1], sys.argv[2], int(sys.argv[3])
    proc = subprocess.Popen([program, tree, str(port)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "ready"
    ctx = zmq.Context()
    req = ctx.socket(zmq.REQ)
    req.setsockopt(zmq.LINGER, 0)
    req.setsockopt(zmq.RCVTIMEO, 5000)
    req.connect(f"tcp://127.0.0.1:{port}")
    out = sys.stdout
    ids = iter(range(1, 1 << 30))

    def header(kind, protocol=2):
        return bytes([protocol, ord(kind)]) + next(ids).to_bytes(4, "little")

    def ask(name, parts):
        req.send_multipart(parts)
        reply = req.recv_multipart()
        out.write(f"request {name} {';'.join(p.hex() for p in parts)}\n")
        out.write(f"reply {';'.join(p.hex() for p in reply)}\n")

    def tick(n):
        proc.stdin.write("tick\n")
        proc.stdin.flush()
        while True:
            line = proc.stdout.readline().split()
            if line[0] == "ticked":
                out.write(f"tick {n} {line[1]}\n")
                return
            out.write(" ".join(line) + "\n")

    # What Groot2 asks when it connects: the tree, its hooks, then recording.
    ask("FULLTREE", [header("T")])
    ask("HOOKS_DUMP", [header("D")])
    ask("TOGGLE_RECORDING", [header("r"), b"start"])
    ask("STATUS", [header("S")])
    for n in range(TICKS):
        tick(n)
        ask("STATUS", [header("S")])
        if n % 3 == 2:
            ask("GET_TRANSITIONS", [header("t")])
    ask("BLACKBOARD", [header("B"), b"MainTree"])
    ask("BLACKBOARD", [header("B"), b"carry;MainTree;nope"])
    ask("BLACKBOARD", [header("B"), b"nope"])
    ask("GET_TRANSITIONS", [header("t")])
    ask("TOGGLE_RECORDING", [header("r"), b"stop"])
    tick(TICKS)
    ask("GET_TRANSITIONS", [header("t")])
    ask("TOGGLE_RECORDING", [header("r"), b"pause"])
    ask("REMOVE_ALL_HOOKS", [header("A")])
    ask("DISABLE_ALL_HOOKS", [header("X")])
    # A bad client: a short header, unknown types, another protocol byte, parts missing.
    ask("short header", [header("S")[:5]])
    ask("long header", [header("S") + b"\0"])
    ask("unknown type", [header("Z")])
    ask("BREAKPOINT_REACHED", [header("N")])
    ask("protocol 9", [header("S", protocol=9)])
    ask("BLACKBOARD alone", [header("B")])
    ask("TOGGLE_RECORDING alone", [header("r")])
    ask("TOGGLE_RECORDING three parts", [header("r"), b"start", b"x"])
    ask("FULLTREE two parts", [header("T"), b"x"])
    ask("STATUS", [header("S")])
    proc.stdin.write("quit\n")
    proc.stdin.flush()
    proc.wait(timeout=10)


if __name__ == "__main__":
    main()
