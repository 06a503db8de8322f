"""Hearing the patient: audio in, what was said out (the ``asr`` node and ``clarc hear``)."""
