//! The explorer's denoiser off the UI thread: a thread of its own runs
//! [`crate::denoise::denoise`] over the running mean the view hands it (on the view's device,
//! as `qjulia render` runs it, so that the bytes agree), one image at a time; an image asked for
//! while another is being denoised waits, and a newer one replaces it, so that the thread never
//! falls behind the passes. The view polls for the result each frame.

use std::sync::Arc;
use std::sync::mpsc::{Receiver, Sender, channel};

use crate::frame::Frame;
use crate::gpu::GpuKernels;
use crate::scene::{Denoise, Scene};

/// What a denoised image was made of: the running mean (its generation in the view) and the
/// `[denoise]` keys.
#[derive(Clone, Debug, PartialEq)]
pub struct DenoiseKey {
    /// Which running mean: the view counts the means it reads back.
    pub generation: u64,
    pub params: Denoise,
}

/// An image to denoise: a whole frame with its AOVs, and the scene whose `image.samples` (the
/// samples in the mean) and `[denoise]` the denoiser reads.
pub struct Request {
    pub key: DenoiseKey,
    pub frame: Arc<Frame>,
    pub scene: Scene,
}

/// A denoised image, or why there is none.
pub struct Done {
    pub key: DenoiseKey,
    pub linear: Result<Vec<[f32; 3]>, String>,
    /// Path mode: the denoised image's estimated relative RMSE (each half denoised alone too,
    /// [`crate::estimate::denoised`]), where the frame has its halves.
    pub estimate: Option<f64>,
    /// Wall seconds of the denoise (the halves' included), and where it ran ("gpu" or "cpu").
    pub seconds: f64,
    pub backend: &'static str,
}

/// The thread, and the image waiting for it.
pub struct DenoiseWorker {
    send: Sender<Request>,
    done: Receiver<Done>,
    /// The key of the image the thread is denoising.
    running: Option<DenoiseKey>,
    /// The next image, sent once the thread is free.
    queued: Option<Request>,
}

impl DenoiseWorker {
    /// The thread, denoising on `kernels`' device.
    pub fn new(kernels: Arc<GpuKernels>) -> Self {
        let (send, requests) = channel::<Request>();
        let (finished, done) = channel();
        let spawned = std::thread::Builder::new()
            .name("qjulia view denoiser".into())
            .spawn(move || {
                // Ends when the view (the sender) is dropped.
                while let Ok(request) = requests.recv() {
                    let denoised = crate::denoise::denoise_estimated(
                        &request.frame,
                        &request.scene,
                        Some(&kernels),
                    );
                    let done = match denoised {
                        Ok((d, estimate)) => Done {
                            key: request.key,
                            linear: Ok(d.linear),
                            estimate: estimate.map(|e| e.relative),
                            seconds: d.seconds,
                            backend: d.backend,
                        },
                        Err(e) => Done {
                            key: request.key,
                            linear: Err(e.to_string()),
                            estimate: None,
                            seconds: 0.0,
                            backend: "",
                        },
                    };
                    if finished.send(done).is_err() {
                        return;
                    }
                }
            });
        if let Err(e) = spawned {
            eprintln!("qjulia: the view's denoiser did not start ({e})");
        }
        Self {
            send,
            done,
            running: None,
            queued: None,
        }
    }

    /// Asks for `request` to be denoised: now if the thread is free, else once it is (in place
    /// of any image already waiting). An image already running or waiting with the same key is
    /// not asked for again.
    pub fn request(&mut self, request: Request) {
        if self.running.as_ref() == Some(&request.key)
            || self.queued.as_ref().is_some_and(|q| q.key == request.key)
        {
            return;
        }
        match self.running {
            Some(_) => self.queued = Some(request),
            None => self.start(request),
        }
    }

    fn start(&mut self, request: Request) {
        self.running = Some(request.key.clone());
        if self.send.send(request).is_err() {
            self.running = None;
        }
    }

    /// The image the thread finished since the last call, if it did; the waiting one is then
    /// sent.
    pub fn poll(&mut self) -> Option<Done> {
        let done = self.done.try_recv().ok()?;
        self.running = None;
        if let Some(next) = self.queued.take() {
            self.start(next);
        }
        Some(done)
    }

    /// Whether an image is being denoised or waits.
    pub fn busy(&self) -> bool {
        self.running.is_some() || self.queued.is_some()
    }

    /// Forgets the image waiting (the view's scene changed); the one running is let finish.
    pub fn drop_queued(&mut self) {
        self.queued = None;
    }
}
