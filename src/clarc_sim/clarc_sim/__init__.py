"""clarc_sim: stand-ins for CLARC's hardware and people (Kinect, microphone and ASR, touch
screen, TTS, a scripted patient, the CGAmed hospital server), so the whole robot runs here."""
