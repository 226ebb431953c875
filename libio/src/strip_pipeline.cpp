#include <algorithm>
#include <chrono>
#include <dhdr/io/image_output.h>
#include <dhdr/io/strip_pipeline.h>
#include <future>

namespace dhdr {

namespace {

double msSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// A stage's result: empty when it succeeded, else why not.
using Outcome = std::future<std::string>;

Outcome launch(bool async, const StripStages::Stage& stage, OIIO::ROI rows, int slot) {
    return std::async(async ? std::launch::async : std::launch::deferred, [&stage, rows, slot] {
        std::string error;
        if (!stage(rows, slot, error)) return error.empty() ? std::string("failed") : error;
        return std::string();
    });
}

// An input's rows read below a strip's own (its halo) and their non-finite values, cleaned
// and not yet counted: counted by the next strip, whose own rows they are, when it copies them
// (shareHalo).
struct RowsBelow {
    OIIO::ROI rows;
    NonFiniteCount count;
};

// Every row of `strip` (own rows `rows`, halo around) read fresh from row `fresh` on cleaned
// once: the halo above (cleaned, or copied clean), the own rows counted into `replaced`, the
// rows below counted by the next strip (returned). Rows copied from the previous strip are
// clean already.
NonFiniteCount cleanStrip(OIIO::ImageBuf& strip, const StripInput& input, OIIO::ROI rows, int fresh,
                          int nthreads, NonFiniteCount& replaced) {
    const OIIO::ROI all = strip.roi();
    auto band = [&](int y0, int y1, int c0, int c1) {
        OIIO::ROI r = all;
        r.ybegin = std::max({y0, fresh, all.ybegin});
        r.yend = std::min(y1, all.yend);
        r.chbegin = c0;
        r.chend = std::min(c1, strip.nchannels());
        return r;
    };
    NonFiniteCount belowOwn;
    for (const auto& [c0, c1] : input.sanitize) {
        if (c1 <= c0) continue;
        if (const OIIO::ROI r = band(all.ybegin, rows.ybegin, c0, c1); r.height() > 0)
            replaceNonFinite(strip, r, nthreads);
        if (const OIIO::ROI r = band(rows.ybegin, rows.yend, c0, c1); r.height() > 0)
            replaced += replaceNonFinite(strip, r, nthreads);
        if (const OIIO::ROI r = band(rows.yend, all.yend, c0, c1); r.height() > 0)
            belowOwn += replaceNonFinite(strip, r, nthreads);
    }
    return belowOwn;
}

// One input's strip `rows` with `halo` rows around into `strip`, the rows it shares with the
// `previous` strip copied from it where `share` allows; its non-finite values cleaned, those of
// its own rows counted into `replaced`; `below` the previous strip's rows below its own before,
// this one's after.
bool readInputStrip(const StripInput& input, OIIO::ROI rows, int halo, bool share, int nthreads,
                    const OIIO::ImageBuf& previous, OIIO::ImageBuf& strip, RowsBelow& below,
                    NonFiniteCount& replaced, std::string& error) {
    // Copied only when the previous strip's rows below its own are this one's first own rows
    // (strips in order), so that they are counted once.
    const bool reuse = share && input.readReusing && previous.initialized() &&
                       below.rows.defined() && below.rows.ybegin == rows.ybegin;
    int copiedEnd = 0;
    const bool ok = reuse ? input.readReusing(rows.ybegin - halo, rows.yend + halo, previous, strip,
                                              copiedEnd, error)
                          : input.read(rows.ybegin - halo, rows.yend + halo, strip, error);
    if (!ok) {
        error = input.name + ": cannot read: " + error;
        return false;
    }
    // Rows copied among the own rows are counted as the previous strip left them.
    const OIIO::ROI all = strip.roi();
    const int fresh = reuse ? std::clamp(copiedEnd, all.ybegin, all.yend) : all.ybegin;
    const NonFiniteCount belowOwn = cleanStrip(strip, input, rows, fresh, nthreads, replaced);
    if (fresh > all.ybegin) {
        // The copied rows: the previous strip's rows below its own, exactly.
        if (fresh != below.rows.yend) {
            error = input.name + ": the strips' shared rows do not match";
            return false;
        }
        replaced += below.count;
    }
    below = {all, belowOwn};
    below.rows.ybegin = std::min(std::max(rows.yend, all.ybegin), all.yend);
    if (below.rows.ybegin >= below.rows.yend) below.rows = OIIO::ROI();
    return true;
}

} // namespace

bool runStrips(OIIO::ROI frame, const StripPipelineParams& params, const StripStages& stages,
               std::string& error) {
    const int rows = std::max(1, params.rows);
    const int strips = frame.height() > 0 ? (frame.height() + rows - 1) / rows : 0;
    auto strip = [&](int k) {
        OIIO::ROI r = frame;
        r.ybegin = frame.ybegin + k * rows;
        r.yend = std::min(r.ybegin + rows, frame.yend);
        return r;
    };
    auto done = [&](Outcome& f) {
        if (!f.valid()) return true;
        const std::string e = f.get();
        if (!e.empty() && error.empty()) error = e;
        return e.empty();
    };
    Outcome reading, writing;
    if (stages.read && strips > 0) reading = launch(params.readAhead, stages.read, strip(0), 0);
    bool ok = true;
    for (int k = 0; k < strips && ok; ++k) {
        const int slot = k % 2;
        ok = done(reading);
        if (!ok) break;
        if (stages.read && k + 1 < strips)
            reading = launch(params.readAhead, stages.read, strip(k + 1), slot ^ 1);
        std::string e;
        if (!stages.process(strip(k), slot, e)) {
            error = e.empty() ? "failed" : e;
            ok = false;
            break;
        }
        // The previous strip's write has finished before this one's starts: writes stay in
        // order, and the slot it read is free for the next process.
        ok = done(writing);
        if (!ok) break;
        if (stages.write) {
            writing = launch(params.writeBehind, stages.write, strip(k), slot);
            if (!params.writeBehind) ok = done(writing);
        }
        if (ok && params.progress) params.progress(float(k + 1) / float(strips));
    }
    // Whatever is in flight ends before the buffers it uses go away.
    ok = done(reading) && ok;
    ok = done(writing) && ok;
    return ok;
}

void StripPipeline::setOutput(
    ImageFileOutput& output,
    std::function<bool(const OIIO::ImageBuf& first, std::string& error)> open) {
    m_output = &output;
    m_open = std::move(open);
}

bool StripPipeline::run(const std::function<bool(StripContext&)>& process) {
    const size_t n = m_inputs.size();
    std::vector<OIIO::ImageBuf> in[2] = {std::vector<OIIO::ImageBuf>(n),
                                         std::vector<OIIO::ImageBuf>(n)};
    OIIO::ImageBuf out[2];
    m_replaced.assign(n, NonFiniteCount());
    m_error.clear();
    const int halo = std::max(0, m_params.halo);
    const bool share = m_params.shareHalo && halo > 0 && halo <= m_params.rows;
    std::vector<RowsBelow> below(n); // per input
    StripStages stages;
    if (n > 0)
        stages.read = [&](OIIO::ROI rows, int slot, std::string& error) {
            const auto t = std::chrono::steady_clock::now();
            for (size_t i = 0; i < n; ++i)
                if (!readInputStrip(m_inputs[i], rows, halo, share, m_params.nthreads,
                                    in[slot ^ 1][i], in[slot][i], below[i], m_replaced[i], error))
                    return false;
            m_readMs += msSince(t);
            return true;
        };
    stages.process = [&](OIIO::ROI rows, int slot, std::string& error) {
        const auto t = std::chrono::steady_clock::now();
        StripContext context;
        context.rows = rows;
        for (OIIO::ImageBuf& b : in[slot])
            context.inputs.push_back(&b);
        context.output = &out[slot];
        const bool ok = process(context);
        if (!ok) error = context.error.empty() ? "cannot process rows" : context.error;
        if (ok && m_output && !m_output->isOpen()) {
            if (!m_open) {
                error = m_output->path() + ": the output was not opened";
                return false;
            }
            if (!m_open(out[slot], error)) return false;
        }
        m_processMs += msSince(t);
        return ok;
    };
    if (m_output)
        stages.write = [&](OIIO::ROI rows, int slot, std::string& error) {
            const auto t = std::chrono::steady_clock::now();
            if (!m_output->writeRows(out[slot], rows)) {
                error = m_output->geterror();
                return false;
            }
            m_writeMs += msSince(t);
            return true;
        };
    return runStrips(m_frame, m_params, stages, m_error);
}

} // namespace dhdr
