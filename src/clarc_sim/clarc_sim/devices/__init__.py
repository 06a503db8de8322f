"""Stand-ins for the robot's devices: the TTS speaker, the microphone with ASR, the touch screen
and the Kinect."""
