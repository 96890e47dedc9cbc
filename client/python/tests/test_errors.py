"""Every exception class, raised with the server's message, and subclassing the builtin
that fits."""

from __future__ import annotations

import numpy as np
import pytest

import gymfleet
from gymfleet import _core


def test_a_bad_document_is_invalid_argument_with_its_json_path(arm2):
    arm2["assembly"]["joints"][1]["child"] = "forarm"
    with pytest.raises(gymfleet.InvalidArgument) as caught:
        gymfleet.make(arm2)
    assert 'assembly.joints[1].child: unknown instance "forarm"' in str(caught.value)
    assert isinstance(caught.value, ValueError) and isinstance(caught.value, gymfleet.GymfleetError)


def test_bad_options_and_actions_are_invalid_argument(arm2):
    with pytest.raises(gymfleet.InvalidArgument, match="substeps: expected an integer from 0 to 4294967295, got -1"):
        gymfleet.make(arm2, substeps=-1)
    with pytest.raises(gymfleet.InvalidArgument, match="seed: expected an integer from 0 to 18446744073709551615, got -5"):
        gymfleet.make(arm2, seed=-5)
    with pytest.raises(gymfleet.InvalidArgument, match="dt"):
        gymfleet.make(arm2, dt=-1.0)
    # Regression: this overflowed the draw's width and panicked on the server (INTERNAL).
    with pytest.raises(gymfleet.InvalidArgument, match=r"reset_noise: expected a half-width of at most 1000000 \(deg or mm\), got 1e308$"):
        gymfleet.make(arm2, reset_noise=1e308)
    with pytest.raises(gymfleet.InvalidArgument, match='action_type: expected "torque", "position" or "velocity", got \'force\''):
        gymfleet.make(arm2, action_type="force")
    env = gymfleet.make(arm2)
    env.reset()
    with pytest.raises(gymfleet.InvalidArgument, match=r"values: expected 2 action values \(one per actuated DOF\), got 1"):
        env.step([0.0])
    with pytest.raises(gymfleet.InvalidArgument, match="expected a finite number, got NaN"):
        env.step([0.0, float("nan")])
    envs = gymfleet.make_vec(arm2, 2)
    with pytest.raises(gymfleet.InvalidArgument, match="num_envs: expected at least 1, got 0"):
        gymfleet.make_vec(arm2, 0)
    with pytest.raises(gymfleet.InvalidArgument, match=r"actions\[3\] \(env 1, value 1\): expected a finite number, got inf"):
        envs.step(np.array([[0, 0], [0, np.inf]]))
    with pytest.raises(gymfleet.InvalidArgument, match="timeout: expected a positive number of seconds"):
        gymfleet.make(arm2, timeout=0)


def test_a_closed_env_is_not_found(arm2):
    env = gymfleet.make(arm2)
    env_id = env.env_id
    env._handle.close()
    with pytest.raises(gymfleet.NotFound) as caught:
        env.step([0.0, 0.0])
    assert env_id in str(caught.value)
    assert caught.value.reason == "ENV_NOT_FOUND"
    assert isinstance(caught.value, KeyError)
    assert str(caught.value) == caught.value.args[0], "no KeyError quoting"


def test_past_a_server_limit_is_resource_exhausted(arm2):
    with gymfleet.Server(max_batch_size=8) as server:
        with pytest.raises(gymfleet.ResourceExhausted, match="8") as caught:
            gymfleet.make_vec(arm2, 9, server=server.address)
        assert "batch" in str(caught.value)
        assert (caught.value.reason, caught.value.limit) == ("LIMIT_EXCEEDED", "--max-batch-size")
        assert gymfleet.server_info(server.address)["batches"] == 0, "nothing half-created"


def test_stepping_a_diverged_env_is_failed_precondition(pendulum):
    env = gymfleet.make(pendulum)
    env.reset()
    _, _, terminated, _, info = env.step([1e12])
    assert terminated and info["termination_reason"] == "physics_diverged"
    with pytest.raises(gymfleet.FailedPrecondition, match="reset") as caught:
        env.step([0.0])
    assert caught.value.reason == "NEEDS_RESET"
    env.reset()
    env.step([0.0])


def test_an_unreachable_server_is_unavailable(arm2):
    with gymfleet.Server() as server:
        address = server.address
    with pytest.raises(gymfleet.Unavailable) as caught:
        gymfleet.make(arm2, server=address)
    assert address in str(caught.value) and caught.value.server == address
    assert isinstance(caught.value, ConnectionError)
    # The words every gymfleet client uses: the address, the cause, the question, and how
    # to point this package elsewhere.
    text = str(caught.value)
    assert text.startswith(f"cannot connect to the gymfleet server at {address}: "), text
    assert text.endswith(
        '. Is the server running? To use another one, pass its address as server="HOST:PORT" '
        "(server=None runs one in this process)."
    ), text


def test_a_call_past_its_timeout_is_deadline_exceeded(arm2):
    with gymfleet.Server(threads=1) as server:
        envs = gymfleet.make_vec(arm2, 4096, server=server.address)
        envs.timeout = 0.001
        assert envs.timeout == 0.001
        with pytest.raises(gymfleet.DeadlineExceeded, match="no reply within the timeout of 0.001 s") as caught:
            envs.step(np.zeros((4096, 2)))
        assert isinstance(caught.value, TimeoutError)


@pytest.mark.parametrize(
    "code,cls,base",
    [
        (3, gymfleet.InvalidArgument, ValueError),
        (5, gymfleet.NotFound, KeyError),
        (8, gymfleet.ResourceExhausted, gymfleet.GymfleetError),
        (9, gymfleet.FailedPrecondition, gymfleet.GymfleetError),
        (16, gymfleet.Unauthenticated, gymfleet.GymfleetError),
        (4, gymfleet.DeadlineExceeded, TimeoutError),
        (14, gymfleet.Unavailable, ConnectionError),
        (13, gymfleet.Internal, gymfleet.GymfleetError),
    ],
)
def test_each_status_raises_its_class_with_the_servers_message(code, cls, base):
    # Statuses no server here can be made to answer (UNAUTHENTICATED before auth
    # exists, INTERNAL) go through the same mapping as every reply.
    with pytest.raises(cls) as caught:
        _core._raise_status(code, "sim_7: the server's words")
    assert str(caught.value) == "sim_7: the server's words"
    assert isinstance(caught.value, base) and isinstance(caught.value, gymfleet.GymfleetError)


def test_a_server_that_requires_a_token_gets_it_from_gymfleet_token(arm2, tmp_path, monkeypatch):
    tokens = tmp_path / "tokens"
    tokens.write_text("# tenant token\npython-team py-token-0123456789abcdef\n")
    # The connection is cached per address, so the variable is set before the first
    # connection to the second server, which runs beside the first: a second server
    # started after the first stopped could get its port, and its cached connection.
    with gymfleet.Server(threads=1, auth_tokens=str(tokens)) as first, gymfleet.Server(
        threads=1, auth_tokens=str(tokens)
    ) as server:
        assert first.address != server.address
        # Without GYMFLEET_TOKEN: refused.
        monkeypatch.delenv("GYMFLEET_TOKEN", raising=False)
        with pytest.raises(gymfleet.Unauthenticated, match="this server requires a token") as caught:
            gymfleet.make(arm2, server=first.address)
        assert caught.value.reason == "UNAUTHENTICATED"
        monkeypatch.setenv("GYMFLEET_TOKEN", "py-token-0123456789abcdef")
        env = gymfleet.make(arm2, server=server.address)
        env.reset(seed=0)
        env.step(np.zeros(2, dtype=np.float32))
        info = gymfleet.server_info(server.address)
        assert info["tenant"] == "python-team" and info["envs"] == 1
        env.close()
    with pytest.raises(gymfleet.InvalidArgument, match="line 1: expected `TENANT TOKEN`"):
        bad = tmp_path / "bad"
        bad.write_text("lonely\n")
        gymfleet.Server(auth_tokens=str(bad))


def test_every_reason_reaches_python_and_what_no_server_said_has_none(arm2, pendulum):
    with pytest.raises(gymfleet.InvalidArgument) as caught:
        gymfleet.make({"parts": [], "assembly": {"instances": [{"part": "X", "name": "x"}]}})
    assert caught.value.reason == "INVALID_DOCUMENT"
    with pytest.raises(gymfleet.InvalidArgument) as caught:
        gymfleet.make(arm2, end_effector_ids=["nowhere"])
    assert caught.value.reason == "UNKNOWN_NAME"
    env = gymfleet.make(pendulum)
    env.reset()
    with pytest.raises(gymfleet.InvalidArgument) as caught:
        env.load_state(b"\x01\x02\x03")
    assert caught.value.reason == "INVALID_STATE"
    env.close()
    # A check the package makes before calling stands in for the server's, with its reason.
    with pytest.raises(gymfleet.InvalidArgument) as caught:
        gymfleet.make_vec(arm2, 0)
    assert caught.value.reason == "INVALID_FIELD"
    # What the package finds itself (no server there) has none.
    with pytest.raises(gymfleet.Unavailable) as caught:
        gymfleet.server_info("127.0.0.1:1")
    assert caught.value.reason is None
    # Every name the proto defines arrives as sent; one this build does not know is None.
    for name in ["INVALID_DOCUMENT", "INVALID_ACTION", "INVALID_STATE", "UNKNOWN_NAME", "INVALID_FIELD",
                 "ENV_NOT_FOUND", "BATCH_NOT_FOUND", "MODEL_NOT_FOUND", "NEEDS_RESET", "NOT_RANDOMIZED",
                 "LIMIT_EXCEEDED", "UNAUTHENTICATED", "INTERNAL", "SHUTTING_DOWN", "FROM_THE_FUTURE"]:
        with pytest.raises(gymfleet.GymfleetError) as caught:
            _core._raise_status(13, "words", name)
        assert caught.value.reason == (None if name == "FROM_THE_FUTURE" else name)


def test_a_document_read_from_a_file_names_the_file_in_its_errors(tmp_path):
    bad = tmp_path / "robot.json"
    bad.write_text('{"parts": [], "assembly": {"instances": [{"part": "X", "name": "x"}]}}')
    for make in (gymfleet.make, lambda d: gymfleet.make_vec(d, 2)):
        for document in (str(bad), bad):
            with pytest.raises(gymfleet.InvalidArgument) as e:
                make(document)
            assert str(e.value) == (
                f"{bad}: assembly.instances[0].part: unknown part \"X\" (known: none)"
            )
    # Given as text, the document has no file to name.
    with pytest.raises(gymfleet.InvalidArgument) as e:
        gymfleet.make(bad.read_text())
    assert str(e.value) == 'assembly.instances[0].part: unknown part "X" (known: none)'


def test_an_unexpected_option_lists_every_keyword(arm2):
    with pytest.raises(TypeError) as e:
        gymfleet.make(arm2, colour=1)
    message = str(e.value)
    assert message.startswith("unexpected option(s) colour; the options are end_effector_ids")
    assert message.endswith("timeout, render_mode, render_options and token")
    with pytest.raises(TypeError) as e:
        gymfleet.make_vec(arm2, 2, colour=1)
    assert str(e.value).endswith("render_options, token and autoreset_mode")


def test_a_token_argument_reaches_a_server_that_requires_one(arm2, tmp_path, monkeypatch):
    token = "py-token-0123456789abcdef"
    tokens = tmp_path / "tokens"
    tokens.write_text(f"python-team {token}\n")
    monkeypatch.delenv("GYMFLEET_TOKEN", raising=False)
    with gymfleet.Server(threads=1, auth_tokens=str(tokens)) as server:
        with pytest.raises(gymfleet.Unauthenticated, match="GYMFLEET_TOKEN"):
            gymfleet.server_info(server.address)
        assert gymfleet.server_info(server.address, token=token)["tenant"] == "python-team"
        assert gymfleet.list_models(server.address, token=token) == []
        env = gymfleet.make(arm2, server=server.address, token=token)
        env.reset(seed=0)
        # The token stays out of the spec, which gets printed and logged; a fork keeps it.
        assert token not in repr(env.spec)
        twin = env.fork()
        twin.close()
        envs = gymfleet.make_vec(arm2, 2, server=server.address, token=token)
        envs.reset(seed=0)
        envs.fork().close()
        envs.close()
        assert gymfleet.server_info(server.address, token=token)["envs"] == 1
        env.close()
        with pytest.raises(gymfleet.InvalidArgument, match="token: expected a non-empty bearer token"):
            gymfleet.make(arm2, server=server.address, token="")
