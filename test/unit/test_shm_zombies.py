"""Fast DDS's shared-memory files of dead processes (ros/shm_zombies.py): a file goes only when
no process holds its lock, read from /proc/locks and never taken, and it is old enough; a port
only in the domains the caller names."""

import fcntl
import os
import time

import pytest

from dsr_graph.ros.shm_zombies import ShmFile, clean, domain_ports, held_locks, zombies

SEGMENT = "fastrtps_0123456789abcdef"
PORT = 7400 + 250 * 58 + 31  # domain 58's, participant 10's user unicast


def files(*names, mtime=0.0, held_from=1000):
    return [ShmFile(n, (0, 27, held_from + i), mtime) for i, n in enumerate(names)]


def port_files(port):
    return [
        f"fastrtps_port{port}",
        f"fastrtps_port{port}_el",
        f"sem.fastrtps_port{port}_mutex",
    ]


def test_proc_locks_name_each_locked_file_by_device_and_inode():
    text = (
        "1: FLOCK  ADVISORY  WRITE 7123 00:1b:4289094 0 EOF\n"
        "2: POSIX  ADVISORY  READ 88 fd:01:12 0 EOF\n"
        "2: -> FLOCK  ADVISORY  WRITE 90 00:1b:77 0 EOF\n"
    )
    assert held_locks(text) == {(0, 27, 4289094), (253, 1, 12), (0, 27, 77)}


def test_a_domains_ports_are_its_250_well_known_ones():
    assert domain_ports(0) == range(7400, 7650)
    assert PORT in domain_ports(58) and PORT not in domain_ports(57)


def test_an_old_unlocked_segment_goes_whole_and_a_locked_or_young_one_stays():
    dead = files(SEGMENT, SEGMENT + "_el")
    assert zombies(dead, held=set(), now=100.0) == sorted([SEGMENT, SEGMENT + "_el"])
    assert zombies(dead, held={dead[1].file_id}, now=100.0) == []
    # made a moment ago: its process may not have locked it yet
    assert zombies(dead, held=set(), now=30.0) == []


def test_a_port_goes_only_in_the_domains_named_and_only_when_nobody_listens():
    port = files(*port_files(PORT))
    assert zombies(port, held=set(), now=100.0) == []  # no domain named: ports stay
    assert zombies(port, held=set(), domains=[57], now=100.0) == []
    assert zombies(port, held=set(), domains=[58], now=100.0) == sorted(port_files(PORT))
    assert zombies(port, held={port[1].file_id}, domains=[58], now=100.0) == []
    assert zombies(port, held=set(), domains=[58], now=5.0) == []  # being made


def test_clean_removes_the_dead_and_leaves_a_file_locked_by_a_living_process(tmp_path):
    old = time.time() - 120
    names = [SEGMENT, SEGMENT + "_el", *port_files(PORT), *port_files(PORT + 2)]
    for name in names:
        (tmp_path / name).write_bytes(b"")
        os.utime(tmp_path / name, (old, old))
    with open(tmp_path / f"fastrtps_port{PORT + 2}_el", "rb") as living:
        fcntl.flock(living, fcntl.LOCK_SH)  # a listener of that port, alive
        removed = clean([58], shm_dir=tmp_path)
        assert sorted(removed) == sorted([SEGMENT, SEGMENT + "_el", *port_files(PORT)])
        assert sorted(p.name for p in tmp_path.iterdir()) == sorted(port_files(PORT + 2))
        # the living process still holds its lock: no other may take it exclusively
        with open(tmp_path / f"fastrtps_port{PORT + 2}_el", "rb") as other:
            with pytest.raises(BlockingIOError):
                fcntl.flock(other, fcntl.LOCK_EX | fcntl.LOCK_NB)
