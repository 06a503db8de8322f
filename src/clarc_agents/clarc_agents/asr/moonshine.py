"""Moonshine base (Useful Sensors, MIT), through ONNX Runtime: a recogniser made apart from
Whisper (its own architecture, trained on other data, no 30 s window), asked for its opinion on
serial answers Whisper leaves unsure (second_opinion.py). On the speech benchmark's audio its
transcripts of serial answers were right less often than Whisper's, but where Whisper misheard
it almost never misheard the same way (BENCHMARKS.md section 9g): its agreement is evidence.

Greedy decoding, as Moonshine's own code does, with the end of text barred at the first step:
the int8 model otherwise often ends at once on an utterance it hears well ("" for a clean
"ninety three, eighty six, ..." at one level, the numbers at another). How sure: the least
likely token of the transcript (the end of text left out), the same bound Whisper's tokens give
a serial answer.
"""

from __future__ import annotations

import math

import numpy as np

from clarc_agents.asr.audio import RATE
from clarc_agents.asr.models import MOONSHINE_BASE, fetched_folder

START, END = 1, 2  # the decoder's start and end-of-text tokens
# a bound on a transcript's length, so that decoding run away on noise stops: people say about
# three words a second, under two tokens each
TOKENS_PER_SECOND = 8
MIN_TOKENS = 8


class MoonshineRecogniser:
    name = "moonshine"

    def __init__(self, threads: int = 2):
        import onnxruntime
        import tokenizers

        folder = fetched_folder(MOONSHINE_BASE)  # ModelError naming what is wrong
        options = onnxruntime.SessionOptions()
        options.intra_op_num_threads, options.inter_op_num_threads = threads, 1
        open_session = lambda name: onnxruntime.InferenceSession(  # noqa: E731
            str(folder / name), options, providers=["CPUExecutionProvider"]
        )
        self.encoder = open_session("encoder_model.onnx")
        self.decoder = open_session("decoder_model_merged.onnx")
        self.tokenizer = tokenizers.Tokenizer.from_file(str(folder / "tokenizer.json"))
        # the cache's shape, as the decoder declares it: (batch, heads, length, head size)
        self._past = {
            i.name: (i.shape[1], i.shape[3])
            for i in self.decoder.get_inputs()
            if i.name.startswith("past_key_values.")
        }
        outputs = [o.name for o in self.decoder.get_outputs()]
        self._present = [name.replace("present.", "past_key_values.", 1) for name in outputs[1:]]

    def hear(self, samples: np.ndarray) -> tuple[str, float]:
        """What was said in ``samples`` (16 kHz mono, int16 or float in [-1, 1]) and how sure:
        ("", 0.0) for nothing."""
        audio = np.asarray(samples, dtype=np.float32)
        if np.issubdtype(np.asarray(samples).dtype, np.integer):
            audio = audio / 32768.0
        if audio.size < RATE // 10:
            return "", 0.0
        hidden = self.encoder.run(None, {"input_values": audio[None, :]})[0]
        past = {
            name: np.zeros((0, heads, 1, size), dtype=np.float32)
            for name, (heads, size) in self._past.items()
        }
        tokens, least = [START], 1.0
        most = max(MIN_TOKENS, int(audio.size / RATE * TOKENS_PER_SECOND))
        for step in range(most):
            inputs = {
                "input_ids": np.array([[tokens[-1]]] if step else [tokens], dtype=np.int64),
                "encoder_hidden_states": hidden,
                "use_cache_branch": np.array([step > 0]),
                **past,
            }
            logits, *present = self.decoder.run(None, inputs)
            scores = logits[0, -1].astype(np.float64)
            if step == 0:
                scores[END] = -math.inf
            token = int(scores.argmax())
            if token == END:
                break
            top = scores[token]
            least = min(least, 1.0 / float(np.exp(scores - top).sum()))
            tokens.append(token)
            for name, value in zip(self._present, present, strict=True):
                if step == 0 or ".decoder." in name:  # the encoder's part is kept from the first
                    past[name] = value
        text = self.tokenizer.decode(tokens[1:]).strip()
        return text, (least if text else 0.0)
